#include "cad_surface.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <fmt/format.h>
#include <gp_Pnt.hxx>

namespace fird {

namespace {

// A uniform cubic B-spline surface over the rectangle from (x0, y0) with knot spacing
// (dx, dy), from its (nu + 2) x (nv + 2) poles' heights q (index k * (nv + 2) + m): pole k
// sits at x0 + (k - 1) dx, the Greville abscissa of uniform cubic knots, so x is linear
// in u and u = x exactly (likewise v = y); the knots x0 + (k - 3) dx are all simple.
// Segment() then clamps the ends to the rectangle by knot insertion, which is exact.
Handle(Geom_BSplineSurface) uniform_bspline(int nu, int nv, double x0, double y0, double dx,
                                            double dy, const std::vector<double>& q) {
    TColgp_Array2OfPnt poles(1, nu + 2, 1, nv + 2);
    for (int k = 0; k < nu + 2; ++k)
        for (int m = 0; m < nv + 2; ++m)
            poles.SetValue(k + 1, m + 1,
                           gp_Pnt(x0 + (k - 1) * dx, y0 + (m - 1) * dy,
                                  q[std::size_t(k) * std::size_t(nv + 2) + std::size_t(m)]));
    const auto knots = [](int n, double origin, double step, TColStd_Array1OfReal& t,
                          TColStd_Array1OfInteger& mult) {
        for (int k = 0; k < n + 6; ++k) {
            t.SetValue(k + 1, origin + (k - 3) * step);
            mult.SetValue(k + 1, 1);
        }
    };
    TColStd_Array1OfReal uk(1, nu + 6), vk(1, nv + 6);
    TColStd_Array1OfInteger um(1, nu + 6), vm(1, nv + 6);
    knots(nu, x0, dx, uk, um);
    knots(nv, y0, dy, vk, vm);
    Handle(Geom_BSplineSurface) s = new Geom_BSplineSurface(poles, uk, vk, um, vm, 3, 3);
    s->Segment(x0, x0 + (nu - 1) * dx, y0, y0 + (nv - 1) * dy);
    return s;
}

// The family's B-spline (surface.cpp: control height (i, j) at (x0 + i dx, y0 + j dy),
// the end heights repeated beyond the grid) term for term.
Handle(Geom_BSplineSurface) exact_bspline(const BSplineFn& f) {
    std::vector<double> q(std::size_t(f.nx + 2) * std::size_t(f.ny + 2));
    for (int k = 0; k < f.nx + 2; ++k)
        for (int m = 0; m < f.ny + 2; ++m) {
            const int i = std::clamp(k - 1, 0, f.nx - 1);
            const int j = std::clamp(m - 1, 0, f.ny - 1);
            q[std::size_t(k) * std::size_t(f.ny + 2) + std::size_t(m)] =
                f.heights[std::size_t(j) * std::size_t(f.nx) + std::size_t(i)];
        }
    return uniform_bspline(f.nx, f.ny, f.x0, f.y0, f.dx, f.dy, q);
}

// Whether every control height lies in the holder's z range: then, by the convex hull
// property, so does the surface, the clamp never acts and the family is the B-spline.
bool within_holder(const BSplineFn& f, const Holder& holder) {
    return std::all_of(f.heights.begin(), f.heights.end(),
                       [&](double h) { return h >= holder.min_mm.z && h <= holder.max_mm.z; });
}

// The n + 2 pole heights of the clamped cubic spline through n values on a uniform grid of
// spacing h with end slopes d0, d1: (q[k] + 4 q[k+1] + q[k+2]) / 6 = f[k] and
// (q[2] - q[0]) / 2h = d0, (q[n+1] - q[n-1]) / 2h = d1; the ends eliminated, the rest is
// tridiagonal and diagonally dominant (Thomas's algorithm). A kink's ringing decays by
// 2 - sqrt 3 per interval, so the error stays where the kink is.
std::vector<double> clamped_spline(const std::vector<double>& f, double h, double d0, double d1) {
    const std::size_t n = f.size();
    std::vector<double> a(n, 1.0), b(n, 4.0), c(n, 1.0), r(n);
    for (std::size_t k = 0; k < n; ++k)
        r[k] = 6.0 * f[k];
    c[0] = 2.0;
    r[0] += 2.0 * h * d0;
    a[n - 1] = 2.0;
    r[n - 1] -= 2.0 * h * d1;
    for (std::size_t k = 1; k < n; ++k) {
        const double w = a[k] / b[k - 1];
        b[k] -= w * c[k - 1];
        r[k] -= w * r[k - 1];
    }
    std::vector<double> q(n + 2);
    q[n] = r[n - 1] / b[n - 1];
    for (std::size_t k = n - 1; k-- > 0;)
        q[k + 1] = (r[k] - c[k] * q[k + 2]) / b[k];
    q[0] = q[2] - 2.0 * h * d0;
    q[n + 1] = q[n - 1] + 2.0 * h * d1;
    return q;
}

// The clamped bicubic spline interpolating the heights on an nx x ny grid over the holder
// rectangle, its edge slopes and corner twists from the family's gradient.
Handle(Geom_BSplineSurface) fit(const HeightFunction& f, int nx, int ny) {
    const Holder& h = f.surface.holder();
    const double x0 = h.min_mm.x, y0 = h.min_mm.y;
    const double dx = (h.max_mm.x - x0) / (nx - 1);
    const double dy = (h.max_mm.y - y0) / (ny - 1);
    const double x1 = x0 + (nx - 1) * dx, y1 = y0 + (ny - 1) * dy;
    // The twist f_xy at the corners: a central difference of f_y (a one-sided one at the rim).
    const auto twist = [&](double x, double y) {
        const double e = 1e-4 * dx;
        const double xa = std::max(x - e, x0), xb = std::min(x + e, x1);
        return (f.gradient(xb, y).y - f.gradient(xa, y).y) / (xb - xa);
    };
    // Along x: every row's heights, and the y-slopes along the two rims y0 and y1.
    const auto along_x = [&](const auto& value, double y, double d0, double d1) {
        std::vector<double> v(std::size_t(nx), 0.0);
        for (int i = 0; i < nx; ++i)
            v[std::size_t(i)] = value(x0 + i * dx, y);
        return clamped_spline(v, dx, d0, d1);
    };
    const auto height = [&](double x, double y) { return f.height(x, y); };
    const auto slope_y = [&](double x, double y) { return f.gradient(x, y).y; };
    std::vector<std::vector<double>> rows;
    for (int j = 0; j < ny; ++j) {
        const double y = y0 + j * dy;
        rows.push_back(along_x(height, y, f.gradient(x0, y).x, f.gradient(x1, y).x));
    }
    const auto rim0 = along_x(slope_y, y0, twist(x0, y0), twist(x1, y0));
    const auto rim1 = along_x(slope_y, y1, twist(x0, y1), twist(x1, y1));
    // Then along y through every row's poles.
    std::vector<double> q(std::size_t(nx + 2) * std::size_t(ny + 2));
    std::vector<double> column(std::size_t(ny), 0.0);
    for (int k = 0; k < nx + 2; ++k) {
        for (int j = 0; j < ny; ++j)
            column[std::size_t(j)] = rows[std::size_t(j)][std::size_t(k)];
        const auto p = clamped_spline(column, dy, rim0[std::size_t(k)], rim1[std::size_t(k)]);
        std::copy(p.begin(), p.end(), q.begin() + std::ptrdiff_t(k) * (ny + 2));
    }
    return uniform_bspline(nx, ny, x0, y0, dx, dy, q);
}

} // namespace

double max_vertical_deviation(const Geom_BSplineSurface& s, const HeightFunction& f, int nx, int ny,
                              glm::dvec2* where) {
    double u0, u1, v0, v1;
    s.Bounds(u0, u1, v0, v1);
    double worst = 0.0;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j) {
            const double u = u0 + (u1 - u0) * i / (nx - 1);
            const double v = v0 + (v1 - v0) * j / (ny - 1);
            const gp_Pnt p = s.Value(u, v);
            const double d = std::abs(p.Z() - f.height(p.X(), p.Y()));
            if (d > worst) {
                worst = d;
                if (where) *where = {p.X(), p.Y()};
            }
        }
    return worst;
}

CadSurface make_cad_surface(const Surface& surface, double tolerance_mm, Heights heights) {
    const HeightFunction f{surface, heights};
    CadSurface c;
    // The check grid: four intervals per fitted interval, so it holds every interval's
    // midpoint, where an interpolating spline strays furthest from a smooth function.
    const auto check = [&](int nx, int ny) {
        c.check_nx = 4 * (nx - 1) + 1;
        c.check_ny = 4 * (ny - 1) + 1;
        c.max_deviation_mm =
            max_vertical_deviation(*c.surface, f, c.check_nx, c.check_ny, &c.worst_xy_mm);
    };
    if (const auto* b = std::get_if<BSplineFn>(&surface.function());
        b && (heights == Heights::Unclamped || within_holder(*b, surface.holder()))) {
        c.surface = exact_bspline(*b);
        c.exact = true;
        c.fit_nx = b->nx;
        c.fit_ny = b->ny;
        check(std::max(b->nx, 65), std::max(b->ny, 65));
        return c;
    }
    // Start near 1 mm spacing (at least 17 samples an axis, at most the limit, for holders
    // of any size), double the intervals until the check passes.
    const Holder& h = surface.holder();
    const double w = h.max_mm.x - h.min_mm.x;
    const double d = h.max_mm.y - h.min_mm.y;
    int nx = int(std::clamp(std::ceil(w) + 1.0, 17.0, double(kMaxFitSamples)));
    int ny = int(std::clamp(std::ceil(d) + 1.0, 17.0, double(kMaxFitSamples)));
    for (;;) {
        c.surface = fit(f, nx, ny);
        c.fit_nx = nx;
        c.fit_ny = ny;
        check(nx, ny);
        if (c.max_deviation_mm <= tolerance_mm) return c;
        if (2 * (nx - 1) + 1 > kMaxFitSamples || 2 * (ny - 1) + 1 > kMaxFitSamples) break;
        nx = 2 * (nx - 1) + 1;
        ny = 2 * (ny - 1) + 1;
    }
    throw CadOptionError(fmt::format(
        "--cad-tolerance {:g} mm: the B-spline fitted to {} x {} heights still deviates by "
        "{:.3g} mm at ({:.2f}, {:.2f}) mm; raise the tolerance",
        tolerance_mm, nx, ny, c.max_deviation_mm, c.worst_xy_mm.x, c.worst_xy_mm.y));
}

} // namespace fird
