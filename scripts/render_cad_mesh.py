#!/usr/bin/python3
"""Renders a gmsh mesh (MSH 2 text: gmsh FILE.step -2 -format msh2 -o FILE.msh) to a PNG,
coloured by height, offscreen with Debian's python3-vtk9: the picture of docs/export.md,
a STEP file as an independent reader sees it.

usage: render_cad_mesh.py MESH.msh OUT.png [TITLE]
"""
import sys

import vtk


def read_msh2(path):
    points, triangles, ids = vtk.vtkPoints(), vtk.vtkCellArray(), {}
    with open(path) as f:
        lines = iter(f.read().splitlines())
    for line in lines:
        if line == "$Nodes":
            for _ in range(int(next(lines))):
                n, x, y, z = next(lines).split()
                ids[int(n)] = points.InsertNextPoint(float(x), float(y), float(z))
        elif line == "$Elements":
            for _ in range(int(next(lines))):
                e = [int(v) for v in next(lines).split()]
                if e[1] == 2:  # 3-node triangle
                    nodes = e[3 + e[2]:]
                    triangles.InsertNextCell(3, [ids[v] for v in nodes])
    mesh = vtk.vtkPolyData()
    mesh.SetPoints(points)
    mesh.SetPolys(triangles)
    return mesh


def main():
    mesh_path, png = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else mesh_path
    mesh = read_msh2(mesh_path)
    heights = vtk.vtkElevationFilter()
    heights.SetInputData(mesh)
    lo, hi = mesh.GetBounds()[4], mesh.GetBounds()[5]
    heights.SetLowPoint(0, 0, lo)
    heights.SetHighPoint(0, 0, hi)
    heights.SetScalarRange(lo, hi)
    lut = vtk.vtkLookupTable()
    lut.SetHueRange(0.66, 0.0)
    lut.Build()
    surface = vtk.vtkPolyDataMapper()
    surface.SetInputConnection(heights.GetOutputPort())
    surface.SetLookupTable(lut)
    surface.SetScalarRange(lo, hi)
    actor = vtk.vtkActor()
    actor.SetMapper(surface)
    edges = vtk.vtkActor()  # gmsh's triangles, to show it is its mesh
    edges_mapper = vtk.vtkPolyDataMapper()
    edges_mapper.SetInputData(mesh)
    edges_mapper.ScalarVisibilityOff()
    edges.SetMapper(edges_mapper)
    edges.GetProperty().SetRepresentationToWireframe()
    edges.GetProperty().SetColor(0.1, 0.1, 0.1)
    edges.GetProperty().SetOpacity(0.25)
    bar = vtk.vtkScalarBarActor()
    bar.SetLookupTable(lut)
    bar.SetTitle("z (mm)")
    bar.SetNumberOfLabels(4)
    bar.SetWidth(0.08)
    text = vtk.vtkTextActor()
    text.SetInput(title)
    text.GetTextProperty().SetFontSize(18)
    text.GetTextProperty().SetColor(0, 0, 0)
    text.SetPosition(10, 10)
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    for a in (actor, edges, bar, text):
        renderer.AddActor(a)
    camera = renderer.GetActiveCamera()
    camera.SetViewUp(0, 0, 1)
    camera.SetPosition(1, -1.6, 1.3)
    camera.SetFocalPoint(0, 0, 0)
    renderer.ResetCamera()
    camera.Zoom(1.3)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(1000, 700)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    writer = vtk.vtkPNGWriter()
    writer.SetFileName(png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()


if __name__ == "__main__":
    main()
