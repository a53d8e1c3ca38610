#include "cad_revolution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <BRepAlgoAPI_Common.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeRevol.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SurfaceOfRevolution.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shell.hxx>
#include <gp_Ax1.hxx>
#include <gp_Pnt.hxx>
#include <gp_Trsf.hxx>

namespace fird {

namespace {

// The meridian in the plane y = cy, x = cx + r, over r in [0, r_end]: the family's
// B-spline term for term (pole k, the control point c_(k-1), at r = (k - 1) spacing, the
// Greville abscissa of the uniform knots (k - 3) spacing, so the parameter is r), its ends
// clamped by Segment (knot insertion, which moves no point).
Handle(Geom_BSplineCurve) meridian(const ProfileFn& f, double r_end) {
    const int nodes = f.spans + 1;
    TColgp_Array1OfPnt poles(1, nodes + 2);
    for (int k = 0; k < nodes + 2; ++k)
        poles.SetValue(k + 1,
                       gp_Pnt(f.cx + (k - 1) * f.spacing, f.cy, f.z0 + f.control[std::size_t(k)]));
    TColStd_Array1OfReal knots(1, nodes + 6);
    TColStd_Array1OfInteger mults(1, nodes + 6);
    for (int k = 0; k < nodes + 6; ++k) {
        knots.SetValue(k + 1, (k - 3) * f.spacing);
        mults.SetValue(k + 1, 1);
    }
    Handle(Geom_BSplineCurve) curve = new Geom_BSplineCurve(poles, knots, mults, 3);
    curve->Segment(0.0, r_end);
    return curve;
}

} // namespace

RevolvedProfile revolve_profile(const Surface& surface) {
    const ProfileFn& f = std::get<ProfileFn>(surface.function());
    const Holder& holder = surface.holder();
    const gp_Ax1 axis(gp_Pnt(f.cx, f.cy, 0.0), gp_Dir(0, 0, 1));
    // The disc must cover the rectangle: out to its farthest corner from the axis.
    const double r_max =
        std::hypot(std::max(std::abs(holder.min_mm.x - f.cx), std::abs(holder.max_mm.x - f.cx)),
                   std::max(std::abs(holder.min_mm.y - f.cy), std::abs(holder.max_mm.y - f.cy)));
    const double radius = f.spans * f.spacing;
    const Handle(Geom_BSplineCurve) curve = meridian(f, std::min(radius, r_max));
    const Handle(Geom_SurfaceOfRevolution) revolved = new Geom_SurfaceOfRevolution(curve, axis);
    // Four quarter turns, each one rational quadratic span around (exact), C2 along the
    // meridian: a sheet's back face is the offset surface of each, which a STEP reader
    // builds only on a basis without a C0 knot line (a half turn has one, where its two
    // arcs meet) and not closed (a whole turn it makes periodic, then fails): OpenCASCADE's
    // own reader drops such a back face. They meet along smooth seam edges.
    RevolvedProfile p;
    BRepBuilderAPI_Sewing sewing(1e-7);
    double z_lo = 1e300, z_hi = -1e300;
    const double quarter = 0.5 * std::numbers::pi;
    // The seams on the diagonals from the axis, not along x and y: an axis on the holder's
    // edge would otherwise put a seam (and the pole) on a face of the trimming box, where
    // OpenCASCADE's Booleans are weakest.
    const double first = 0.5 * quarter;
    for (int k = 0; k < 4; ++k) {
        const Handle(Geom_BSplineSurface) half =
            GeomConvert::SurfaceToBSplineSurface(new Geom_RectangularTrimmedSurface(
                revolved, first + k * quarter, first + (k + 1) * quarter, Standard_True));
        p.quarters[std::size_t(k)] = half;
        for (int i = 1; i <= half->NbUPoles(); ++i)
            for (int j = 1; j <= half->NbVPoles(); ++j) {
                z_lo = std::min(z_lo, half->Pole(i, j).Z());
                z_hi = std::max(z_hi, half->Pole(i, j).Z());
            }
        sewing.Add(BRepBuilderAPI_MakeFace(half, 1e-7).Face());
    }

    // The flat beyond radius_mm, where it lies in the holder: a plane annulus (quarter turns
    // of the line r in [radius_mm, r_max] at f(radius_mm)), meeting the spline's faces along
    // a circle, a kink wherever f'(radius_mm) is not 0.
    const double* c = &f.control[std::size_t(f.spans)];
    p.slope_at_radius = 0.5 * (c[2] - c[0]) / f.spacing;
    const double r_min =
        std::hypot(std::max({holder.min_mm.x - f.cx, 0.0, f.cx - holder.max_mm.x}),
                   std::max({holder.min_mm.y - f.cy, 0.0, f.cy - holder.max_mm.y}));
    p.kink = r_max > radius && radius > r_min && std::abs(p.slope_at_radius) > 1e-9;
    if (r_max > radius) {
        const gp_Pnt rim = curve->EndPoint();
        const TopoDS_Edge line =
            BRepBuilderAPI_MakeEdge(rim, gp_Pnt(f.cx + r_max, f.cy, rim.Z())).Edge();
        for (int k = 0; k < 4; ++k) {
            gp_Trsf turn;
            turn.SetRotation(axis, first + k * quarter);
            sewing.Add(
                BRepPrimAPI_MakeRevol(line.Moved(TopLoc_Location(turn)), axis, quarter).Shape());
        }
    }
    sewing.Perform();

    // Trimmed to the rectangle: the part inside the holder's box, whose floor and top lie
    // beyond every pole (the convex hull holds the surface).
    const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(holder.min_mm.x, holder.min_mm.y, z_lo - 1),
                                                 gp_Pnt(holder.max_mm.x, holder.max_mm.y, z_hi + 1))
                                 .Shape();
    BRepAlgoAPI_Common common(sewing.SewedShape(), box);
    if (!common.IsDone() || common.HasErrors())
        throw std::runtime_error("OpenCASCADE could not trim the revolved profile to the holder");
    // The pieces in the box as one shell (the Boolean keeps the edges they share). The
    // normal D1U x D1V of a revolved meridian points down (the angle turns counter-
    // clockwise, the meridian runs outwards): each face goes in reversed, so its normal is
    // the reflecting side's (the faces, not the shell, for a fillet rebuilds the shell).
    BRep_Builder builder;
    TopoDS_Shell shell;
    builder.MakeShell(shell);
    int faces = 0;
    for (TopExp_Explorer e(common.Shape(), TopAbs_FACE); e.More(); e.Next(), ++faces)
        builder.Add(shell, e.Current().Reversed());
    if (faces == 0 || !BRepCheck_Analyzer(shell).IsValid())
        throw std::runtime_error("OpenCASCADE made no valid surface of the revolved profile in "
                                 "the holder rectangle");
    p.faces = shell;
    p.trim_tolerance_mm = BRep_Tool::MaxTolerance(shell, TopAbs_EDGE);

    // Every point of the check grid inside the holder against the family: eight samples a
    // knot interval along the meridian (every interval's midpoint among them), at least 129
    // along each quarter turn. (The flat annulus is a plane at the family's last height.)
    p.check_nu = 129;
    p.check_nv = std::max(257, 8 * (p.quarters[0]->NbVKnots() - 1) + 1);
    for (const Handle(Geom_BSplineSurface) & half : p.quarters) {
        double u0, u1, v0, v1;
        half->Bounds(u0, u1, v0, v1);
        for (int i = 0; i < p.check_nu; ++i)
            for (int j = 0; j < p.check_nv; ++j) {
                const gp_Pnt q = half->Value(u0 + (u1 - u0) * i / (p.check_nu - 1),
                                             v0 + (v1 - v0) * j / (p.check_nv - 1));
                if (q.X() < holder.min_mm.x || q.X() > holder.max_mm.x || q.Y() < holder.min_mm.y ||
                    q.Y() > holder.max_mm.y)
                    continue;
                const double d = std::abs(q.Z() - surface.raw(q.X(), q.Y()));
                if (d > p.max_deviation_mm) {
                    p.max_deviation_mm = d;
                    p.worst_xy_mm = {q.X(), q.Y()};
                }
            }
    }
    return p;
}

} // namespace fird
