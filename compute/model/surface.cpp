#include "surface.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "mesh.hpp"

namespace fird {

namespace {

double param(const ReflectorDesc& r, const char* name) {
    const auto it = r.parameters.find(name);
    if (it == r.parameters.end())
        throw std::invalid_argument(std::string("reflector parameter '") + name + "' is missing");
    return it->second;
}

void require(bool ok, const char* name, const char* rule) {
    if (!ok)
        throw std::invalid_argument(std::string("reflector parameter '") + name + "' must be " +
                                    rule);
}

// Range of (v - c)^2 ... over v in [v0, v1]: of |v - c|.
HeightRange distance_range(double v0, double v1, double c) {
    const double lo = (c < v0) ? v0 - c : (c > v1 ? c - v1 : 0.0);
    const double hi = std::max(std::abs(v0 - c), std::abs(v1 - c));
    return {lo, hi};
}

// Range of k * g(u) for u in [u0, u1] with g increasing and k of either sign.
HeightRange scaled(double k, double g0, double g1) {
    return {std::min(k * g0, k * g1), std::max(k * g0, k * g1)};
}

// floor(s) within [lo, hi], compared as doubles first: converting a double beyond int's
// range is undefined (a far box or a tiny spacing from a scene file gives such an s), and a
// NaN s gives hi.
int clamped_floor(double s, int lo, int hi) {
    if (!(s < double(hi))) return hi;
    if (!(s > double(lo))) return lo;
    return int(std::floor(s));
}

// Uniform cubic B-spline basis functions and their derivatives at t in [0, 1).
void basis(double t, double b[4], double db[4]) {
    const double t2 = t * t;
    const double t3 = t2 * t;
    const double s = 1.0 - t;
    b[0] = s * s * s / 6.0;
    b[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
    b[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
    b[3] = t3 / 6.0;
    db[0] = -s * s / 2.0;
    db[1] = (9.0 * t2 - 12.0 * t) / 6.0;
    db[2] = (-9.0 * t2 + 6.0 * t + 3.0) / 6.0;
    db[3] = t2 / 2.0;
}

// f(r) and f'(r) of a profile: the span holding r (beyond the last knot, f there and no
// slope).
std::pair<double, double> profile_value_slope(const ProfileFn& f, double r) {
    const double s = r / f.spacing;
    if (!(s < double(f.spans))) {
        const std::size_t n = std::size_t(f.spans);
        return {(f.control[n] + 4.0 * f.control[n + 1] + f.control[n + 2]) / 6.0, 0.0};
    }
    const int i = clamped_floor(s, 0, f.spans - 1);
    double b[4], db[4];
    basis(s - i, b, db);
    double v = 0.0, d = 0.0;
    for (int k = 0; k < 4; ++k) {
        v += b[k] * f.control[std::size_t(i + k)]; // c_(i-1+k) sits at control[i + k]
        d += db[k] * f.control[std::size_t(i + k)];
    }
    return {v, d / f.spacing};
}

struct Raw {
    double x, y;
    // Every point of the holder rectangle lies over a triangle (checked at load); the
    // fallback only catches points a rounding error outside the mesh's rim.
    double operator()(const MeshFn& f) const { return f.field->height(x, y).value_or(-1e300); }
    double operator()(const PlaneFn& f) const {
        return f.z0 + f.sx * (x - f.cx) + f.sy * (y - f.cy);
    }
    double operator()(const ParaboloidFn& f) const {
        const double u = x - f.cx;
        const double v = y - f.cy;
        return f.z0 + u * u / (4.0 * f.fx) + v * v / (4.0 * f.fy);
    }
    double operator()(const CupFn& f) const {
        return f.z0 + f.h * std::pow(std::abs(x - f.cx) / f.a, f.p) +
               f.h * std::pow(std::abs(y - f.cy) / f.b, f.p);
    }
    double operator()(const FlutedCupFn& f) const {
        const double u = x - f.cx;
        const double v = y - f.cy;
        const double rho = std::hypot(u, v) / f.a;
        const double psi = std::atan2(v, u);
        return f.z0 + f.h * std::pow(rho, f.p) + f.w * rho * std::cos(8.0 * psi);
    }
    double operator()(const BSplineFn& f) const {
        const double sx = std::clamp((x - f.x0) / f.dx, 0.0, double(f.nx - 1));
        const double sy = std::clamp((y - f.y0) / f.dy, 0.0, double(f.ny - 1));
        const int i = std::min(int(sx), f.nx - 2 < 0 ? 0 : f.nx - 2);
        const int j = std::min(int(sy), f.ny - 2 < 0 ? 0 : f.ny - 2);
        double bx[4], dbx[4], by[4], dby[4];
        basis(sx - i, bx, dbx);
        basis(sy - j, by, dby);
        double z = 0.0;
        for (int m = 0; m < 4; ++m)
            for (int k = 0; k < 4; ++k) {
                const int ci = std::clamp(i - 1 + k, 0, f.nx - 1);
                const int cj = std::clamp(j - 1 + m, 0, f.ny - 1);
                z += by[m] * bx[k] * f.heights[std::size_t(cj) * f.nx + ci];
            }
        return z;
    }
    double operator()(const ProfileFn& f) const {
        return f.z0 + profile_value_slope(f, std::hypot(x - f.cx, y - f.cy)).first;
    }
};

struct RawGradient {
    double x, y;
    glm::dvec2 operator()(const MeshFn& f) const {
        glm::dvec2 g{0.0};
        (void)f.field->height(x, y, &g);
        return g;
    }
    glm::dvec2 operator()(const PlaneFn& f) const { return {f.sx, f.sy}; }
    glm::dvec2 operator()(const ParaboloidFn& f) const {
        return {(x - f.cx) / (2.0 * f.fx), (y - f.cy) / (2.0 * f.fy)};
    }
    glm::dvec2 operator()(const CupFn& f) const {
        const double u = x - f.cx;
        const double v = y - f.cy;
        const auto term = [&](double d, double s) {
            if (d == 0.0) return 0.0;
            return f.h * f.p * std::pow(std::abs(d) / s, f.p - 1.0) / s * (d > 0 ? 1.0 : -1.0);
        };
        return {term(u, f.a), term(v, f.b)};
    }
    glm::dvec2 operator()(const FlutedCupFn& f) const {
        const double u = x - f.cx;
        const double v = y - f.cy;
        const double r = std::hypot(u, v);
        if (r == 0.0) return {0.0, 0.0}; // the apex: the flutes vanish with rho
        const double rho = r / f.a;
        const double psi = std::atan2(v, u);
        // dz/drho and dz/dpsi, then the chain rule to x, y.
        const double dz_drho = f.h * f.p * std::pow(rho, f.p - 1.0) + f.w * std::cos(8.0 * psi);
        const double dz_dpsi = -8.0 * f.w * rho * std::sin(8.0 * psi);
        const double drho_dx = u / (r * f.a);
        const double drho_dy = v / (r * f.a);
        const double dpsi_dx = -v / (r * r);
        const double dpsi_dy = u / (r * r);
        return {dz_drho * drho_dx + dz_dpsi * dpsi_dx, dz_drho * drho_dy + dz_dpsi * dpsi_dy};
    }
    glm::dvec2 operator()(const BSplineFn& f) const {
        const double sx = (x - f.x0) / f.dx;
        const double sy = (y - f.y0) / f.dy;
        const double cx = std::clamp(sx, 0.0, double(f.nx - 1));
        const double cy = std::clamp(sy, 0.0, double(f.ny - 1));
        const int i = std::min(int(cx), std::max(f.nx - 2, 0));
        const int j = std::min(int(cy), std::max(f.ny - 2, 0));
        double bx[4], dbx[4], by[4], dby[4];
        basis(cx - i, bx, dbx);
        basis(cy - j, by, dby);
        glm::dvec2 g{0.0};
        for (int m = 0; m < 4; ++m)
            for (int k = 0; k < 4; ++k) {
                const int ci = std::clamp(i - 1 + k, 0, f.nx - 1);
                const int cj = std::clamp(j - 1 + m, 0, f.ny - 1);
                const double h = f.heights[std::size_t(cj) * f.nx + ci];
                g.x += by[m] * dbx[k] * h / f.dx;
                g.y += dby[m] * bx[k] * h / f.dy;
            }
        // Outside the control grid the spline is held constant along the clamped axis.
        if (sx != cx) g.x = 0.0;
        if (sy != cy) g.y = 0.0;
        return g;
    }
    glm::dvec2 operator()(const ProfileFn& f) const {
        const double u = x - f.cx;
        const double v = y - f.cy;
        const double r = std::hypot(u, v);
        if (r == 0.0) return {0.0, 0.0}; // f'(0) = 0 by construction
        const double slope = profile_value_slope(f, r).second;
        return {slope * u / r, slope * v / r};
    }
};

struct RawBounds {
    double x0, x1, y0, y1;
    HeightRange operator()(const MeshFn& f) const {
        const auto [lo, hi] = f.field->bounds(x0, x1, y0, y1);
        return {lo, hi};
    }
    HeightRange operator()(const PlaneFn& f) const {
        const auto a = scaled(f.sx, x0 - f.cx, x1 - f.cx);
        const auto b = scaled(f.sy, y0 - f.cy, y1 - f.cy);
        return {f.z0 + a.lo + b.lo, f.z0 + a.hi + b.hi};
    }
    HeightRange operator()(const ParaboloidFn& f) const {
        const auto u = distance_range(x0, x1, f.cx);
        const auto v = distance_range(y0, y1, f.cy);
        const auto a = scaled(1.0 / (4.0 * f.fx), u.lo * u.lo, u.hi * u.hi);
        const auto b = scaled(1.0 / (4.0 * f.fy), v.lo * v.lo, v.hi * v.hi);
        return {f.z0 + a.lo + b.lo, f.z0 + a.hi + b.hi};
    }
    HeightRange operator()(const CupFn& f) const {
        const auto u = distance_range(x0, x1, f.cx);
        const auto v = distance_range(y0, y1, f.cy);
        const auto a = scaled(f.h, std::pow(u.lo / f.a, f.p), std::pow(u.hi / f.a, f.p));
        const auto b = scaled(f.h, std::pow(v.lo / f.b, f.p), std::pow(v.hi / f.b, f.p));
        return {f.z0 + a.lo + b.lo, f.z0 + a.hi + b.hi};
    }
    HeightRange operator()(const FlutedCupFn& f) const {
        const auto u = distance_range(x0, x1, f.cx);
        const auto v = distance_range(y0, y1, f.cy);
        const double rho_lo = std::hypot(u.lo, v.lo) / f.a;
        const double rho_hi = std::hypot(u.hi, v.hi) / f.a;
        const auto radial = scaled(f.h, std::pow(rho_lo, f.p), std::pow(rho_hi, f.p));
        // The flutes F = w rho cos 8 psi: |F| <= |w| rho_hi, and F is Lipschitz with
        // |grad F| = |w|/a sqrt(cos^2 + 64 sin^2) <= |w| sqrt(65) / a, so around the box
        // centre it varies by at most that times the half diagonal. The tighter of the two
        // shrinks with the box, which keeps the reference tracer's subdivision shallow.
        const double cx = 0.5 * (x0 + x1) - f.cx;
        const double cy = 0.5 * (y0 + y1) - f.cy;
        const double rc = std::hypot(cx, cy);
        const double centre = rc > 0.0 ? f.w * rc / f.a * std::cos(8.0 * std::atan2(cy, cx)) : 0.0;
        const double spread =
            std::abs(f.w) * std::sqrt(65.0) / f.a * 0.5 * std::hypot(x1 - x0, y1 - y0);
        const double crude = std::abs(f.w) * rho_hi;
        const double flute_lo = std::max(-crude, centre - spread);
        const double flute_hi = std::min(crude, centre + spread);
        return {f.z0 + radial.lo + flute_lo, f.z0 + radial.hi + flute_hi};
    }
    HeightRange operator()(const BSplineFn& f) const {
        // Convex hull property: the surface lies within its influencing control heights.
        const auto index = [](double s, int n) { return clamped_floor(s, 0, n - 1); };
        const int i0 = std::max(index((x0 - f.x0) / f.dx, f.nx) - 1, 0);
        const int i1 = std::min(index((x1 - f.x0) / f.dx, f.nx) + 2, f.nx - 1);
        const int j0 = std::max(index((y0 - f.y0) / f.dy, f.ny) - 1, 0);
        const int j1 = std::min(index((y1 - f.y0) / f.dy, f.ny) + 2, f.ny - 1);
        HeightRange r{1e300, -1e300};
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const double h = f.heights[std::size_t(j) * f.nx + i];
                r.lo = std::min(r.lo, h);
                r.hi = std::max(r.hi, h);
            }
        return r;
    }
    HeightRange operator()(const ProfileFn& f) const {
        // f over the box's radii [r_lo, r_hi], exactly: in each span it reaches, the cubic at
        // the interval's ends and where its derivative (a quadratic in t) vanishes between
        // them. Tight bounds that shrink with the box keep the reference tracer's
        // subdivision shallow (a span's convex hull would not shrink below the span).
        const auto u = distance_range(x0, x1, f.cx);
        const auto v = distance_range(y0, y1, f.cy);
        const double r_lo = std::hypot(u.lo, v.lo), r_hi = std::hypot(u.hi, v.hi);
        HeightRange r{1e300, -1e300};
        const auto include = [&](double radius) {
            const double z = profile_value_slope(f, radius).first;
            r.lo = std::min(r.lo, z);
            r.hi = std::max(r.hi, z);
        };
        include(r_lo);
        include(r_hi);
        const double end = f.spacing * f.spans;
        for (int i = clamped_floor(r_lo / f.spacing, 0, f.spans);
             i < f.spans && i * f.spacing < r_hi; ++i) {
            const double* c = &f.control[std::size_t(i)];
            // f'(t) spacing = A t^2 + B t + C (the basis derivatives of basis()).
            const double A = -0.5 * c[0] + 1.5 * c[1] - 1.5 * c[2] + 0.5 * c[3];
            const double B = c[0] - 2.0 * c[1] + c[2];
            const double C = 0.5 * (c[2] - c[0]);
            const double t0 = std::max(0.0, r_lo / f.spacing - i);
            const double t1 = std::min(1.0, std::min(r_hi, end) / f.spacing - i);
            const auto root = [&](double t) {
                // Inclusive: an extreme on a knot is t = 1 of one span and t = 0 of the next.
                if (t >= t0 && t <= t1) include((i + t) * f.spacing);
            };
            if (std::abs(A) < 1e-300) {
                if (B != 0.0) root(-C / B);
            } else if (const double disc = B * B - 4.0 * A * C; disc >= 0.0) {
                const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
                root(q / A);
                if (q != 0.0) root(C / q);
            }
        }
        // Rounding in the cubic's evaluation: a margin far below a texel.
        const double margin = 1e-9 * (1.0 + std::abs(r.lo) + std::abs(r.hi));
        return {f.z0 + r.lo - margin, f.z0 + r.hi + margin};
    }
};

} // namespace

std::vector<double> profile_control_points(const std::vector<double>& h) {
    if (h.size() < 2) throw std::invalid_argument("a profile needs at least two heights");
    const std::size_t n = h.size() - 1;
    // Rows k = 0 .. n of A c = 6 h: row 0 (4, 2) (c_-1 = c_1), rows 1 .. n-1 (1, 4, 1),
    // row n c_n = h_n (the natural end folds c_n+1 into it). Forward sweep, back substitution.
    std::vector<double> diag(n + 1, 4.0), upper(n + 1, 1.0), lower(n + 1, 1.0), rhs(n + 1);
    for (std::size_t k = 0; k <= n; ++k)
        rhs[k] = 6.0 * h[k];
    upper[0] = 2.0;
    diag[n] = 6.0;
    lower[n] = 0.0;
    for (std::size_t k = 1; k <= n; ++k) {
        const double m = lower[k] / diag[k - 1];
        diag[k] -= m * upper[k - 1];
        rhs[k] -= m * rhs[k - 1];
    }
    std::vector<double> c(n + 3);
    c[n + 1] = rhs[n] / diag[n];
    for (std::size_t k = n; k-- > 0;)
        c[k + 1] = (rhs[k] - upper[k] * c[k + 2]) / diag[k];
    c[0] = c[2];                      // c_-1 = c_1
    c[n + 2] = 2.0 * c[n + 1] - c[n]; // c_n+1 = 2 c_n - c_n-1
    return c;
}

bool in_control_group(const ControlGroup& group, int i, int j, int nx, int ny) {
    switch (group.kind) {
    case ControlGroup::Kind::Point:
        return i == group.i && j == group.j;
    case ControlGroup::Kind::Row:
        return j == group.i;
    case ControlGroup::Kind::Column:
        return i == group.i;
    case ControlGroup::Kind::Ring:
        return std::min({i, j, nx - 1 - i, ny - 1 - j}) == group.i;
    }
    return false;
}

std::vector<double> bspline_heights(const BSplineDesc& s,
                                    const std::map<std::string, double>& parameters) {
    std::vector<double> h = s.heights_mm;
    for (const auto& [name, group] : s.groups) {
        const auto it = parameters.find(name);
        if (it == parameters.end()) continue;
        for (int j = 0; j < s.ny; ++j)
            for (int i = 0; i < s.nx; ++i)
                if (in_control_group(group, i, j, s.nx, s.ny))
                    h[std::size_t(j) * s.nx + i] = it->second;
    }
    return h;
}

Surface Surface::make(const ReflectorDesc& r, const Holder& holder) {
    switch (r.family) {
    case Family::Plane:
        return {
            PlaneFn{param(r, "z0"), param(r, "sx"), param(r, "sy"), param(r, "cx"), param(r, "cy")},
            holder};
    case Family::Paraboloid: {
        const ParaboloidFn f{param(r, "fx"), param(r, "fy"), param(r, "z0"), param(r, "cx"),
                             param(r, "cy")};
        require(f.fx > 0.0, "fx", "> 0");
        require(f.fy > 0.0, "fy", "> 0");
        return {f, holder};
    }
    case Family::Cup: {
        const CupFn f{param(r, "a"),  param(r, "b"),  param(r, "p"), param(r, "h"),
                      param(r, "z0"), param(r, "cx"), param(r, "cy")};
        require(f.a > 0.0, "a", "> 0");
        require(f.b > 0.0, "b", "> 0");
        require(f.p >= 1.0, "p", ">= 1");
        return {f, holder};
    }
    case Family::FlutedCup: {
        const FlutedCupFn f{param(r, "a"),  param(r, "p"),  param(r, "h"), param(r, "w"),
                            param(r, "z0"), param(r, "cx"), param(r, "cy")};
        require(f.a > 0.0, "a", "> 0");
        require(f.p >= 1.0, "p", ">= 1");
        return {f, holder};
    }
    case Family::BSpline: {
        const auto& s = r.bspline;
        if (s.nx < 2 || s.ny < 2 || s.heights_mm.size() != std::size_t(s.nx) * s.ny)
            throw std::invalid_argument("bspline needs a grid of at least 2 x 2 control heights");
        const Holder& h = holder;
        return {BSplineFn{s.nx, s.ny, h.min_mm.x, h.min_mm.y,
                          (h.max_mm.x - h.min_mm.x) / (s.nx - 1),
                          (h.max_mm.y - h.min_mm.y) / (s.ny - 1), bspline_heights(s, r.parameters)},
                holder};
    }
    case Family::Profile: {
        const auto& s = r.bspline;
        if (s.nx < 2 || s.ny != 1 || s.heights_mm.size() != std::size_t(s.nx))
            throw std::invalid_argument("a profile needs at least two heights");
        const double radius = param(r, "radius_mm");
        require(radius > 0.0, "radius_mm", "> 0");
        return {ProfileFn{param(r, "z0"), param(r, "cx"), param(r, "cy"), radius / (s.nx - 1),
                          s.nx - 1, profile_control_points(bspline_heights(s, r.parameters))},
                holder};
    }
    case Family::Mesh: {
        TriangleMesh mesh = load_mesh(r.mesh.resolved_path, r.mesh.unit_mm);
        return {MeshFn{std::make_shared<const MeshHeightField>(std::move(mesh), holder,
                                                               r.mesh.resolved_path)},
                holder};
    }
    }
    throw std::invalid_argument("unknown reflector family");
}

double Surface::raw(double x, double y) const {
    return std::visit(Raw{x, y}, fn_);
}

glm::dvec2 Surface::raw_gradient(double x, double y) const {
    return std::visit(RawGradient{x, y}, fn_);
}

double Surface::height(double x, double y) const {
    return std::clamp(raw(x, y), holder_.min_mm.z, holder_.max_mm.z);
}

glm::dvec2 Surface::gradient(double x, double y) const {
    const double z = raw(x, y);
    // On the clamp plateaus the surface is flat.
    if (z <= holder_.min_mm.z || z >= holder_.max_mm.z) return {0.0, 0.0};
    return raw_gradient(x, y);
}

HeightRange Surface::bounds(double x0, double x1, double y0, double y1) const {
    const HeightRange r = std::visit(RawBounds{x0, x1, y0, y1}, fn_);
    const double zmin = holder_.min_mm.z;
    const double zmax = holder_.max_mm.z;
    return {std::clamp(r.lo, zmin, zmax), std::clamp(r.hi, zmin, zmax)};
}

} // namespace fird
