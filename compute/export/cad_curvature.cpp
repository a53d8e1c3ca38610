#include "cad_curvature.hpp"

#include <algorithm>
#include <limits>

#include <GeomLProp_SLProps.hxx>

namespace fird {

BackCurvature smallest_back_radius(const Handle(Geom_Surface) & s, const Holder& holder, int nx,
                                   int ny) {
    double u0, u1, v0, v1;
    s->Bounds(u0, u1, v0, v1);
    GeomLProp_SLProps props(s, 2, 1e-9);
    // The curvatures are signed about the normal D1U x D1V, which points up (+z) for the
    // height-field form S(u, v) = (u, v, z) and down for a revolved meridian: turned up, a
    // negative one bends towards the back.
    double most_negative = 0.0;
    BackCurvature r{std::numeric_limits<double>::infinity(), {0.0, 0.0}};
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            const double u = u0 + (u1 - u0) * i / (nx - 1);
            const double v = v0 + (v1 - v0) * j / (ny - 1);
            props.SetParameters(u, v);
            const gp_Pnt p = props.Value();
            if (p.X() < holder.min_mm.x || p.X() > holder.max_mm.x || p.Y() < holder.min_mm.y ||
                p.Y() > holder.max_mm.y || p.Z() < holder.min_mm.z || p.Z() > holder.max_mm.z ||
                !props.IsNormalDefined() || !props.IsCurvatureDefined())
                continue;
            const double k =
                props.Normal().Z() > 0.0 ? props.MinCurvature() : -props.MaxCurvature();
            // A bend of a kilometre's radius is a flat's rounding error (a revolved
            // surface's flat evaluates to curvatures of 1e-18 per mm), not a bend.
            if (k < most_negative && k < -1e-6) {
                most_negative = k;
                r = {-1.0 / k, {props.Value().X(), props.Value().Y()}};
            }
        }
    return r;
}

} // namespace fird
