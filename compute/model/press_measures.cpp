#include "press_measures.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

namespace fird {

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;
// A normal turning by more than this (radians) over the difference step is a kink: the
// smallest radius the differences resolve is the step over it (20 steps).
constexpr double kKinkTurn = 0.05;

// The mean (H) and Gaussian (K) curvatures of z = f(x, y) with gradient (p, q) and
// Hessian [[r, s], [s, t]] (the graph's shape operator).
struct Curvatures {
    double mean, gauss;
    // The larger principal curvature in magnitude, |H| + sqrt(H^2 - K).
    double largest() const {
        return std::abs(mean) + std::sqrt(std::max(mean * mean - gauss, 0.0));
    }
    // k1^2 + k2^2 = (k1 + k2)^2 - 2 k1 k2 = 4 H^2 - 2 K (at least 0 in exact arithmetic).
    double squared_sum() const { return std::max(4.0 * mean * mean - 2.0 * gauss, 0.0); }
};
Curvatures curvatures(double p, double q, double r, double s, double t) {
    const double w = 1.0 + p * p + q * q;
    return {.mean = ((1.0 + q * q) * r - 2.0 * p * q * s + (1.0 + p * p) * t) /
                    (2.0 * std::pow(w, 1.5)),
            .gauss = (r * t - s * s) / (w * w)};
}

// The derivative along one axis of the analytic gradient at t (in [lo, hi]): central
// differences, or at the holder's rim (the family is not defined beyond it: a B-spline is
// held constant there) the one-sided second-order formula, so the error is e^2 times the
// gradient's third (central: / 6) or second-and-third (one-sided: / 3) derivative
// everywhere. The step e is a hundredth of the grid's: that error stays far below the
// change of curvature between samples, and the rounding (1e-16 |gradient| / e) far below
// any curvature a press can form.
template <class Gradient>
glm::dvec2 derivative(const Gradient& g, double t, double lo, double hi, double e) {
    if (t - e < lo) return (-3.0 * g(t) + 4.0 * g(t + e) - g(t + 2.0 * e)) / (2.0 * e);
    if (t + e > hi) return (3.0 * g(t) - 4.0 * g(t - e) + g(t - 2.0 * e)) / (2.0 * e);
    return (g(t + e) - g(t - e)) / (2.0 * e);
}

struct Hessian {
    double r, s, t;
};
Hessian hessian(const Surface& surf, double x, double y, double e) {
    const Holder& h = surf.holder();
    const glm::dvec2 along_x =
        derivative([&](double u) { return surf.raw_gradient(u, y); }, x, h.min_mm.x, h.max_mm.x, e);
    const glm::dvec2 along_y =
        derivative([&](double v) { return surf.raw_gradient(x, v); }, y, h.min_mm.y, h.max_mm.y, e);
    // The mixed derivative both ways, averaged (equal for a smooth surface).
    return {along_x.x, 0.5 * (along_x.y + along_y.x), along_y.y};
}

// Where along a rim, between samples a (d_a > 0 below the top) and b (d_b <= 0), the
// edge meets the holder's top: linear in the raw height's depth below it.
double crossing(double d_a, double d_b) {
    return d_a / (d_a - d_b);
}

struct RimSide {
    const char* name;
    glm::dvec2 start, end; // along the side
    int n;                 // samples
};

void find_walls(const Surface& surf, const RimSide& side, std::vector<RimWall>& out) {
    const double top = surf.holder().max_mm.z;
    const double span = top - surf.holder().min_mm.z;
    const auto at = [&](double u) { return side.start + (side.end - side.start) * u; };
    const auto depth = [&](int k) {
        const glm::dvec2 p = at(double(k) / (side.n - 1));
        return top - surf.raw(p.x, p.y);
    };
    const double length = glm::length(side.end - side.start);
    const double du = 1.0 / (side.n - 1);
    int k = 0;
    while (k < side.n) {
        if (!(depth(k) > 0.0)) {
            ++k;
            continue;
        }
        // A wall from the crossing before sample k to the one after its last sample.
        double u0 = double(k) * du;
        if (k > 0) u0 = (double(k) - crossing(depth(k), depth(k - 1))) * du;
        double tallest = 0.0;
        int last = k;
        while (last < side.n && depth(last) > 0.0) {
            tallest = std::max(tallest, std::min(depth(last), span));
            ++last;
        }
        double u1 = double(last - 1) * du;
        if (last < side.n) u1 = (double(last - 1) + crossing(depth(last - 1), depth(last))) * du;
        out.push_back({side.name, at(u0), at(u1), (u1 - u0) * length, tallest});
        k = last;
    }
}

// How much higher than `sampled` (the largest sample) the values may rise between samples:
// within a cell they may exceed its largest corner by up to the spread of its corners (one
// step's change), so the largest of (largest corner + spread) over the cells, less the
// sample. Cells with a clamped corner count their unclamped corners. An estimate from the
// samples (a feature narrower than a cell goes unseen), local to where the extreme can be.
double missed_by_cells(const std::vector<double>& v, int nx, int ny, double sampled) {
    double worst = sampled;
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            for (const std::size_t k :
                 {std::size_t(j) * nx + i, std::size_t(j) * nx + i + 1, std::size_t(j + 1) * nx + i,
                  std::size_t(j + 1) * nx + i + 1})
                if (!std::isnan(v[k])) {
                    lo = std::min(lo, v[k]);
                    hi = std::max(hi, v[k]);
                }
            if (hi >= lo) worst = std::max(worst, hi + (hi - lo));
        }
    return worst - sampled;
}

// Every stride-th index of 0 .. n - 1, and n - 1.
std::vector<int> strided(int n, int stride) {
    std::vector<int> out;
    for (int i = 0; i < n - 1; i += std::max(stride, 1))
        out.push_back(i);
    out.push_back(n - 1);
    return out;
}

// The trapezoid rule's weight of sample a of the indices (in grid steps).
double cell_share(const std::vector<int>& indices, int a) {
    const std::size_t k = std::size_t(a);
    const double before = k > 0 ? indices[k] - indices[k - 1] : 0.0;
    const double after = k + 1 < indices.size() ? indices[k + 1] - indices[k] : 0.0;
    return 0.5 * (before + after);
}

} // namespace

PressMeasures press_measures(const Surface& surface, const PressOptions& options) {
    const Holder& h = surface.holder();
    const double wx = h.max_mm.x - h.min_mm.x, wy = h.max_mm.y - h.min_mm.y;
    const double step = std::max(wx, wy) / kPressGridIntervals;
    return press_measures(surface, std::max(2, int(std::ceil(wx / step - 1e-9)) + 1),
                          std::max(2, int(std::ceil(wy / step - 1e-9)) + 1), options);
}

double search_bending_energy(const Surface& surface) {
    return press_measures(surface, PressOptions{.curvature = true, .stride = 4}).bending_energy;
}

PressMeasures press_measures(const Surface& surface, int nx, int ny, const PressOptions& options) {
    const Holder& h = surface.holder();
    PressMeasures m;
    m.nx = nx;
    m.ny = ny;
    m.dx_mm = (h.max_mm.x - h.min_mm.x) / (nx - 1);
    m.dy_mm = (h.max_mm.y - h.min_mm.y) / (ny - 1);
    const double e = 0.01 * std::min(m.dx_mm, m.dy_mm);
    const bool faceted = std::holds_alternative<MeshFn>(surface.function());
    // The samples measured: every stride-th of the grid and its last (a subset of the
    // full grid's samples, each measured as there).
    const std::vector<int> is = strided(nx, options.stride), js = strided(ny, options.stride);
    const int cx = int(is.size()), cy = int(js.size());
    const std::size_t count = std::size_t(cx) * std::size_t(cy);
    // Per sample: slope and curvature (NaN where clamped), kept to bound the sampling error.
    std::vector<double> slope(count, std::nan("")), curvature(count, std::nan(""));
    double lowest = HUGE_VAL, highest = -HUGE_VAL, max_curvature = -1.0, max_slope = -1.0;
    for (int b = 0; b < cy; ++b)
        for (int a = 0; a < cx; ++a) {
            const int i = is[std::size_t(a)], j = js[std::size_t(b)];
            const double x = h.min_mm.x + i * m.dx_mm, y = h.min_mm.y + j * m.dy_mm;
            const std::size_t k = std::size_t(b) * cx + a;
            const double raw = surface.raw(x, y);
            const double z = std::clamp(raw, h.min_mm.z, h.max_mm.z);
            lowest = std::min(lowest, z);
            highest = std::max(highest, z);
            const double weight = cell_share(is, a) * cell_share(js, b) * m.dx_mm * m.dy_mm;
            // Where the family is outside the holder's z range the clamp holds it flat.
            if (raw < h.min_mm.z || raw > h.max_mm.z) {
                m.area_mm2 += weight; // a flat of the clamp
                continue;
            }
            m.any_unclamped = true;
            const glm::dvec2 g = surface.raw_gradient(x, y);
            const double norm = std::hypot(g.x, g.y);
            m.area_mm2 += weight * std::sqrt(1.0 + norm * norm);
            m.unclamped_area_mm2 += weight * std::sqrt(1.0 + norm * norm);
            slope[k] = std::atan(norm) * kDeg;
            if (slope[k] > max_slope) {
                max_slope = slope[k];
                m.max_slope_at_mm = {x, y};
            }
            if (faceted || !options.curvature) continue;
            const Hessian hs = hessian(surface, x, y, e);
            const Curvatures c = curvatures(g.x, g.y, hs.r, hs.s, hs.t);
            curvature[k] = c.largest();
            // The bending energy's element: k1^2 + k2^2 over the surface's own area. A
            // sample on a kink (the test below) is left out: there the differences read the
            // jump of the gradient over the step, a curvature of the grid, not of the part.
            if (curvature[k] * e <= kKinkTurn)
                m.bending_energy += weight * std::sqrt(1.0 + norm * norm) * c.squared_sum();
            // Below the differences' rounding (a few ulps of the gradient over the step) a
            // curvature is noise: a plane has none.
            if (curvature[k] <= 8.0 * std::numeric_limits<double>::epsilon() * (1.0 + norm) / e)
                curvature[k] = 0.0;
            if (curvature[k] > max_curvature) {
                max_curvature = curvature[k];
                m.min_radius_at_mm = {x, y};
            }
        }
    m.depth_mm = highest - lowest;
    m.max_slope_deg = std::max(max_slope, 0.0);
    if (faceted || !options.curvature) {
        m.min_radius_mm = std::nan("");
        m.bending_energy = std::nan("");
    } else if (max_curvature * e > kKinkTurn) {
        // The gradient turns by more over the difference step than any curvature it can
        // resolve: a kink (the fluted cup's apex, a cup of power below 2), radius 0.
        m.kink = true;
        m.min_radius_mm = 0.0;
    } else if (max_curvature > 0.0)
        m.min_radius_mm = 1.0 / max_curvature;
    m.slope_error_deg = missed_by_cells(slope, cx, cy, m.max_slope_deg);
    if (!m.kink && max_curvature > 0.0)
        m.curvature_error_per_mm = missed_by_cells(curvature, cx, cy, max_curvature);
    const glm::dvec2 lo{h.min_mm.x, h.min_mm.y}, hi{h.max_mm.x, h.max_mm.y};
    for (const RimSide& side :
         {RimSide{"y_min", lo, {hi.x, lo.y}, nx}, RimSide{"x_max", {hi.x, lo.y}, hi, ny},
          RimSide{"y_max", {lo.x, hi.y}, hi, nx}, RimSide{"x_min", lo, {lo.x, hi.y}, ny}})
        find_walls(surface, side, m.rim_walls);
    if (options.maps) {
        m.maps.nx = cx;
        m.maps.ny = cy;
        m.maps.slope_deg.assign(slope.begin(), slope.end());
        m.maps.curvature_per_mm.assign(curvature.begin(), curvature.end());
    }
    return m;
}

std::vector<ConstraintCheck> check_constraints(const PressMeasures& m, const ConstraintsDesc& c) {
    std::vector<ConstraintCheck> out;
    const auto at_most = [&](const char* name, double value, double limit) {
        const bool met = value <= limit;
        out.push_back({name, value, limit, met, met ? 0.0 : (value - limit) / limit});
    };
    if (c.max_slope_deg) at_most("max_slope_deg", m.max_slope_deg, *c.max_slope_deg);
    if (c.min_radius_mm) {
        // A NaN radius (a mesh's facets) is never shown to meet a limit.
        const bool met = m.min_radius_mm >= *c.min_radius_mm;
        const double violation =
            met ? 0.0
                : (std::isnan(m.min_radius_mm)
                       ? 1.0
                       : (*c.min_radius_mm - m.min_radius_mm) / *c.min_radius_mm);
        out.push_back({"min_radius_mm", m.min_radius_mm, *c.min_radius_mm, met, violation});
    }
    if (c.max_depth_mm) at_most("max_depth_mm", m.depth_mm, *c.max_depth_mm);
    return out;
}

std::vector<ConstraintCheck> constraint_checks(const Surface& surface, const ConstraintsDesc& c) {
    PressOptions options{.curvature = c.min_radius_mm.has_value(), .stride = 8};
    std::vector<ConstraintCheck> coarse = check_constraints(press_measures(surface, options), c);
    if (std::any_of(coarse.begin(), coarse.end(), [](const ConstraintCheck& k) { return !k.met; }))
        return coarse;
    options.stride = 1;
    return check_constraints(press_measures(surface, options), c);
}

} // namespace fird
