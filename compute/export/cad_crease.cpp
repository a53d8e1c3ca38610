#include "cad_crease.hpp"

#include <cmath>
#include <optional>
#include <stdexcept>

#include <BRepAlgoAPI_BuilderAlgo.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <Geom_Plane.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>
#include <gp_Pln.hxx>

namespace fird {

namespace {

// A point strictly inside a face (a grid over its parameter box, classified against its
// boundary): the centre of an annulus-like flange piece may lie in its hole.
std::optional<gp_Pnt> inside_point(const TopoDS_Face& face) {
    double u0, u1, v0, v1;
    BRepTools::UVBounds(face, u0, u1, v0, v1);
    BRepTopAdaptor_FClass2d classifier(face, 1e-7);
    const Handle(Geom_Surface) s = BRep_Tool::Surface(face);
    for (int n = 8; n <= 256; n *= 2)
        for (int i = 1; i < n; ++i)
            for (int j = 1; j < n; ++j) {
                const gp_Pnt2d uv(u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n);
                if (classifier.Perform(uv) == TopAbs_IN) return s->Value(uv.X(), uv.Y());
            }
    return std::nullopt;
}

} // namespace

Creases clamp_creases(const Surface& surface) {
    const Holder& h = surface.holder();
    Creases c;
    for (int i = 0; i <= 256; ++i)
        for (int j = 0; j <= 256; ++j) {
            const double z = surface.raw(h.min_mm.x + (h.max_mm.x - h.min_mm.x) * i / 256,
                                         h.min_mm.y + (h.max_mm.y - h.min_mm.y) * j / 256);
            c.top = c.top || z > h.max_mm.z;
            c.floor = c.floor || z < h.min_mm.z;
            c.above_top_mm = std::max(c.above_top_mm, z - h.max_mm.z);
            c.below_floor_mm = std::max(c.below_floor_mm, h.min_mm.z - z);
        }
    return c;
}

std::vector<double> flat_areas(const TopoDS_Shape& shell, double z) {
    std::vector<double> areas;
    for (TopExp_Explorer e(shell, TopAbs_FACE); e.More(); e.Next()) {
        const TopoDS_Face face = TopoDS::Face(e.Current());
        const Handle(Geom_Plane) plane = Handle(Geom_Plane)::DownCast(BRep_Tool::Surface(face));
        if (plane.IsNull() || std::abs(plane->Location().Z() - z) > 1e-9) continue;
        GProp_GProps area;
        BRepGProp::SurfaceProperties(face, area);
        areas.push_back(area.Mass());
    }
    return areas;
}

TopoDS_Shape creased_shell(const TopoDS_Shape& unclamped, const Surface& surface,
                           const Creases& creases) {
    const Holder& h = surface.holder();
    const auto plane = [&](double z) {
        return BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0.0, 0.0, z), gp_Dir(0, 0, 1)), h.min_mm.x,
                                       h.max_mm.x, h.min_mm.y, h.max_mm.y)
            .Face();
    };
    // The general fuse splits each face along the others, and the pieces share the crease
    // edges, so the shell below is connected without sewing.
    BRepAlgoAPI_BuilderAlgo fuse;
    TopTools_ListOfShape arguments;
    arguments.Append(unclamped);
    if (creases.top) arguments.Append(plane(h.max_mm.z));
    if (creases.floor) arguments.Append(plane(h.min_mm.z));
    fuse.SetArguments(arguments);
    fuse.Build();
    if (!fuse.IsDone() || fuse.HasErrors())
        throw std::runtime_error("OpenCASCADE could not cut the reflector at the holder's top "
                                 "or floor");
    BRep_Builder builder;
    TopoDS_Shell shell;
    builder.MakeShell(shell);
    int faces = 0;
    for (TopExp_Explorer e(fuse.Shape(), TopAbs_FACE); e.More(); e.Next()) {
        const TopoDS_Face piece = TopoDS::Face(e.Current());
        const std::optional<gp_Pnt> p = inside_point(piece);
        if (!p) continue; // a sliver with no interior
        const bool flat = !Handle(Geom_Plane)::DownCast(BRep_Tool::Surface(piece)).IsNull();
        const double raw = surface.raw(p->X(), p->Y());
        // The holder's top or floor (a flat of the family's own, a profile's beyond its
        // radius, is the family's).
        const bool holder_plane =
            flat && (std::abs(p->Z() - h.max_mm.z) < 1e-9 || std::abs(p->Z() - h.min_mm.z) < 1e-9);
        // The family between the two, a flange where it rises above the top, a floor where
        // it dips below the holder's floor.
        const bool keep =
            !holder_plane
                ? p->Z() > h.min_mm.z && p->Z() < h.max_mm.z
                : (p->Z() > 0.5 * (h.min_mm.z + h.max_mm.z) ? raw > h.max_mm.z : raw < h.min_mm.z);
        if (keep) {
            builder.Add(shell, piece);
            ++faces;
        }
    }
    if (faces == 0 || !BRepCheck_Analyzer(shell).IsValid())
        throw std::runtime_error("OpenCASCADE made no valid surface of the reflector and its "
                                 "flat clamped parts");
    return shell;
}

} // namespace fird
