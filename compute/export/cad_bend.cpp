#include "cad_bend.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <BRepAdaptor_Curve.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Geom_Plane.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <fmt/format.h>

#include "cad_option_error.hpp"
#include "cad_step.hpp"

namespace fird {

namespace {

bool is_flat(const TopoDS_Shape& face) {
    return !Handle(Geom_Plane)::DownCast(BRep_Tool::Surface(TopoDS::Face(face))).IsNull();
}

// The point halfway along an edge, for naming it.
gp_Pnt midpoint(const TopoDS_Edge& e) {
    const BRepAdaptor_Curve c(e);
    return c.Value(0.5 * (c.FirstParameter() + c.LastParameter()));
}

// The largest |z - f| over a face's points on a 33 x 33 grid of its parameter box (those
// inside its boundary).
void measure(const TopoDS_Face& face, const Surface& surface, Bend& bend) {
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    BRepTopAdaptor_FClass2d inside(face, 1e-7);
    const Handle(Geom_Surface) s = BRep_Tool::Surface(face);
    for (int i = 0; i <= 32; ++i)
        for (int j = 0; j <= 32; ++j) {
            const gp_Pnt2d uv(u0 + (u1 - u0) * i / 32, v0 + (v1 - v0) * j / 32);
            if (inside.Perform(uv) == TopAbs_OUT) continue;
            const gp_Pnt p = s->Value(uv.X(), uv.Y());
            const double d = std::abs(p.Z() - surface.height(p.X(), p.Y()));
            if (d > bend.max_deviation_mm) {
                bend.max_deviation_mm = d;
                bend.worst_xy_mm = {p.X(), p.Y()};
            }
        }
}

} // namespace

TopoDS_Shape bent_sheet(const TopoDS_Shape& shell, const Surface& surface, double radius_mm,
                        double thickness_mm, Bend& bend) {
    bend.radius_mm = radius_mm;
    // The creases: edges between a flat piece and a piece of the family.
    TopTools_IndexedDataMapOfShapeListOfShape faces_of;
    TopExp::MapShapesAndAncestors(shell, TopAbs_EDGE, TopAbs_FACE, faces_of);
    BRepFilletAPI_MakeFillet fillet(shell);
    for (int i = 1; i <= faces_of.Extent(); ++i) {
        const TopTools_ListOfShape& faces = faces_of.FindFromIndex(i);
        if (faces.Extent() != 2 || is_flat(faces.First()) == is_flat(faces.Last())) continue;
        const TopoDS_Edge edge = TopoDS::Edge(faces_of.FindKey(i));
        fillet.Add(radius_mm, edge);
        GProp_GProps length;
        BRepGProp::LinearProperties(edge, length);
        bend.crease_length_mm += length.Mass();
        ++bend.creases;
    }
    const auto refused = [&](const std::string& why) {
        return CadOptionError(fmt::format("--bend-radius {:g}: {}", radius_mm, why));
    };
    if (bend.creases == 0) return thickened(shell, thickness_mm); // nothing to bend
    try {
        fillet.Build();
    } catch (const Standard_Failure&) {
    }
    if (!fillet.IsDone()) {
        // Name a crease it could not round: the first whose fillet alone fails.
        for (int i = 1; i <= fillet.NbContours(); ++i) {
            const TopoDS_Edge& edge = fillet.Edge(i, 1);
            BRepFilletAPI_MakeFillet one(shell);
            one.Add(radius_mm, edge);
            try {
                one.Build();
            } catch (const Standard_Failure&) {
            }
            if (one.IsDone()) continue;
            const gp_Pnt p = midpoint(edge);
            GProp_GProps length;
            BRepGProp::LinearProperties(edge, length);
            throw refused(fmt::format(
                "OpenCASCADE cannot round the crease through ({:.2f}, {:.2f}, {:.2f}) mm, {:.3g} "
                "mm long, with this radius (a sheet needs its creases bent)",
                p.X(), p.Y(), p.Z(), length.Mass()));
        }
        throw refused("OpenCASCADE cannot round the creases together with this radius");
    }
    const TopoDS_Shape rounded = fillet.Shape();
    // The bends' faces: those the fillet made (neither flat nor the family's).
    for (TopExp_Explorer e(rounded, TopAbs_FACE); e.More(); e.Next()) {
        const TopoDS_Face face = TopoDS::Face(e.Current());
        bool original = is_flat(face);
        for (TopExp_Explorer o(shell, TopAbs_FACE); !original && o.More(); o.Next())
            original = BRep_Tool::Surface(TopoDS::Face(o.Current())) == BRep_Tool::Surface(face);
        if (!original) measure(face, surface, bend);
    }
    TopoDS_Shape top = rounded;
    for (TopExp_Explorer e(rounded, TopAbs_SHELL); e.More(); e.Next())
        top = e.Current();
    try {
        return thickened(top, thickness_mm);
    } catch (const std::runtime_error& e) {
        throw refused(fmt::format("{} (a bend towards the back needs a radius over the "
                                  "thickness)",
                                  e.what()));
    }
}

} // namespace fird
