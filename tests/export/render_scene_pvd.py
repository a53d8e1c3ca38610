# Loads an export's scene.pvd in ParaView and renders it offscreen (pvpython).
# Usage: pvpython render_scene_pvd.py EXPORT_DIR OUT.png
import sys

from paraview.simple import GetActiveViewOrCreate, OpenDataFile, ResetCamera, SaveScreenshot, Show

source = OpenDataFile(sys.argv[1] + "/scene.pvd")
if source is None:
    sys.exit("scene.pvd did not open")
view = GetActiveViewOrCreate("RenderView")
Show(source, view)
ResetCamera(view)
SaveScreenshot(sys.argv[2], view, ImageResolution=[640, 480])
