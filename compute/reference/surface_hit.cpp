#include "surface_hit.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace fird {

namespace {
constexpr double kLeafLength_mm = 1e-4;
constexpr double kRootTolerance_mm = 1e-12;
constexpr int kMaxBisections = 80;
constexpr int kMaxStack = 128; // depth <= log2(box diagonal / leaf) + slack

double gap(const Surface& s, const Ray& r, double t) {
    const glm::dvec3 p = r.origin + t * r.direction;
    return p.z - s.height(p.x, p.y);
}
} // namespace

glm::dvec3 surface_normal(const Surface& surface, double x, double y) {
    const glm::dvec2 g = surface.gradient(x, y);
    return glm::normalize(glm::dvec3(-g.x, -g.y, 1.0));
}

SurfaceHit first_surface_hit(const Surface& s, const Ray& r, double t_min) {
    const Holder& h = s.holder();
    double t_enter = 0.0;
    double t_exit = 0.0;
    if (!clip_to_box(r, h.min_mm, h.max_mm, t_enter, t_exit)) return {};
    t_enter = std::max(t_enter, t_min);
    if (t_enter >= t_exit) return {};

    const double g0 = gap(s, r, t_enter);
    if (g0 <= 0.0 && t_enter > t_min) {
        // Entering the box at or below the surface: through the top face onto a plateau at
        // the holder's top is a hit right there; through a side face it meets the back of
        // the reflector (absorbed).
        const double z = r.origin.z + t_enter * r.direction.z;
        if (std::abs(z - h.max_mm.z) <= 1e-9 * (1.0 + std::abs(h.max_mm.z)))
            return {HitStart::Above, t_enter};
        if (g0 < 0.0) return {HitStart::Blocked, {}};
    }
    if (g0 < 0.0) {
        // Inside the solid at the start of the search.
        return {t_min > 0.0 ? HitStart::Above : HitStart::BelowSurface,
                t_min > 0.0 ? std::optional<double>(t_min) : std::nullopt};
    }

    struct Segment {
        double a, b;
    };
    Segment stack[kMaxStack];
    int top = 0;
    stack[top++] = {t_enter, t_exit};
    while (top > 0) {
        const Segment seg = stack[--top];
        const glm::dvec3 pa = r.origin + seg.a * r.direction;
        const glm::dvec3 pb = r.origin + seg.b * r.direction;
        const HeightRange range = s.bounds(std::min(pa.x, pb.x), std::max(pa.x, pb.x),
                                           std::min(pa.y, pb.y), std::max(pa.y, pb.y));
        if (std::min(pa.z, pb.z) > range.hi) continue; // wholly above the surface here
        if (seg.b - seg.a <= kLeafLength_mm || top + 2 > kMaxStack) {
            if (gap(s, r, seg.b) > 0.0) continue;
            // g(a) > 0 >= g(b): bisect.
            double lo = seg.a;
            double hi = seg.b;
            for (int i = 0; i < kMaxBisections && hi - lo > kRootTolerance_mm; ++i) {
                const double mid = 0.5 * (lo + hi);
                (gap(s, r, mid) > 0.0 ? lo : hi) = mid;
            }
            return {HitStart::Above, hi};
        }
        const double mid = 0.5 * (seg.a + seg.b);
        stack[top++] = {mid, seg.b}; // far half later
        stack[top++] = {seg.a, mid}; // near half first
    }
    return {};
}

} // namespace fird
