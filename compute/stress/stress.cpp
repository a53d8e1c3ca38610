#include "stress/stress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "fastpath/fast_tracer.hpp"
#include "reference/reference_tracer.hpp"
#include "reference/surface_hit.hpp"

namespace fird {

namespace {

double p99(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(0.99 * double(v.size())))];
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The shares of rays a case may lose to the discretization of the surface (a ray that
// grazes a silhouette can land on either side of it): above that, it fails.
constexpr double kMaxTunnelled = 0.005, kMaxSpurious = 0.005, kMaxExtra = 0.01;

} // namespace

StressResult run_stress_case(const vk::Context& ctx, const StressCase& c) {
    StressResult r{.name = c.name, .note = c.note};
    const Scene& s = c.scene;
    const Surface surface = Surface::make(s.reflector, s.holder);
    const std::vector<Ray> rays = c.rays.empty() ? sample_effective_rays(s, c.sample) : c.rays;
    r.rays = rays.size();
    FastTracer fast(ctx, s, s.trace.seed);
    fast.set_reflector(s.reflector);

    // First hits, ray by ray.
    std::vector<glm::vec4> hits;
    const FastRun first = fast.run_rays(rays, &hits);
    r.aborted += first.aborted;
    const double tx = (s.holder.max_mm.x - s.holder.min_mm.x) / s.trace.heightfield_w;
    const double ty = (s.holder.max_mm.y - s.holder.min_mm.y) / s.trace.heightfield_h;
    std::vector<double> errors;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const glm::vec4 h = hits[i];
        if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z) ||
            !std::isfinite(h.w))
            ++r.nonfinite;
        const SurfaceHit ref = first_surface_hit(surface, rays[i], 0.0);
        const bool fast_hit = h.w >= 0.0f, ref_hit = ref.t.has_value();
        if (ref_hit && !fast_hit) {
            ++r.tunnelled;
            if (std::getenv("FIRD_STRESS_DEBUG"))
                std::fprintf(stderr,
                             "tunnelled: o (%.9g, %.9g, %.9g) d (%.9g, %.9g, %.9g) ref t %.9g\n",
                             rays[i].origin.x, rays[i].origin.y, rays[i].origin.z,
                             rays[i].direction.x, rays[i].direction.y, rays[i].direction.z, *ref.t);
        }
        if (fast_hit && !ref_hit && ref.start == HitStart::Above) ++r.spurious;
        if (fast_hit && ref_hit) {
            const glm::dvec3 p = rays[i].origin + *ref.t * rays[i].direction;
            errors.push_back(
                std::max(std::abs(double(h.x) - p.x) / tx, std::abs(double(h.y) - p.y) / ty));
        }
    }
    r.hit_error_p99_texels = p99(errors);

    // Whole paths: reflections and leaving directions against the reference's.
    const auto paths = fast.trace_paths(rays);
    std::vector<double> angles;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        for (const glm::dvec3& v : paths[i].vertices)
            if (!finite(v)) ++r.nonfinite;
        const PathResult ref =
            trace_path(surface, s.holder, rays[i], s.trace.max_bounces, s.trace.bounce_policy);
        if (ref.fate == RayFate::Lost || ref.fate == RayFate::BelowSurface) continue;
        if (paths[i].reflections > ref.reflections) ++r.extra_reflections;
        if (paths[i].reflections == ref.reflections && paths[i].reflections > 0)
            angles.push_back(std::acos(std::clamp(
                glm::dot(glm::normalize(paths[i].direction), glm::normalize(ref.direction)), -1.0,
                1.0)));
    }
    r.direction_error_p99_rad = p99(angles);

    // The scene's own rays through the whole pipeline: energy balance, a finite far field.
    try {
        const FastRun run = fast.run();
        r.aborted += run.aborted;
        for (double v : fast.read_farfield())
            if (!std::isfinite(v)) ++r.nonfinite;
    } catch (const std::logic_error&) {
        r.energy_balanced = false; // FastTracer::finish checks emitted = the sum of fates
    }

    const double n = double(std::max<std::uint64_t>(r.rays, 1));
    const auto fail = [&](std::string why) {
        if (r.ok) r.failure = std::move(why);
        r.ok = false;
    };
    if (r.aborted) fail(fmt::format("{} rays aborted", r.aborted));
    if (r.nonfinite) fail(fmt::format("{} NaN or Inf values", r.nonfinite));
    if (!r.energy_balanced) fail("energy not balanced");
    if (c.compare_surface) {
        if (double(r.tunnelled) > kMaxTunnelled * n)
            fail(fmt::format("{} rays tunnelled through the surface", r.tunnelled));
        if (double(r.spurious) > kMaxSpurious * n)
            fail(fmt::format("{} spurious hits", r.spurious));
        if (r.hit_error_p99_texels > c.hit_tolerance_texels)
            fail(fmt::format("hit error p99 {:.3g} texels > {:.3g}", r.hit_error_p99_texels,
                             c.hit_tolerance_texels));
    }
    if (c.compare_surface && c.compare_paths) {
        if (double(r.extra_reflections) > kMaxExtra * n)
            fail(fmt::format("{} paths with extra reflections (self-hits)", r.extra_reflections));
        if (r.direction_error_p99_rad > c.direction_tolerance_rad)
            fail(fmt::format("direction error p99 {:.3g} rad > {:.3g}", r.direction_error_p99_rad,
                             c.direction_tolerance_rad));
    }
    return r;
}

nlohmann::json stress_json(const std::vector<StressResult>& results) {
    nlohmann::json cases = nlohmann::json::array();
    bool ok = true;
    for (const StressResult& r : results) {
        ok = ok && r.ok;
        cases.push_back({{"case", r.name},
                         {"rays", r.rays},
                         {"aborted", r.aborted},
                         {"nonfinite", r.nonfinite},
                         {"tunnelled", r.tunnelled},
                         {"spurious", r.spurious},
                         {"extra_reflections", r.extra_reflections},
                         {"hit_error_p99_texels", r.hit_error_p99_texels},
                         {"direction_error_p99_rad", r.direction_error_p99_rad},
                         {"energy_balanced", r.energy_balanced},
                         {"ok", r.ok},
                         {"failure", r.failure},
                         {"note", r.note}});
    }
    return {{"cases", cases}, {"ok", ok}};
}

std::string stress_table(const std::vector<StressResult>& results) {
    std::string s = fmt::format("{:<48} {:>6} {:>7} {:>6} {:>8} {:>8} {:>6} {:>10} {:>10}  {}\n",
                                "case", "rays", "aborted", "NaN", "tunnel", "spurious", "extra",
                                "hit p99 tx", "dir p99", "result");
    for (const StressResult& r : results)
        s += fmt::format("{:<48} {:>6} {:>7} {:>6} {:>8} {:>8} {:>6} {:>10.3g} {:>10.3g}  {}\n",
                         r.name, r.rays, r.aborted, r.nonfinite, r.tunnelled, r.spurious,
                         r.extra_reflections, r.hit_error_p99_texels, r.direction_error_p99_rad,
                         r.ok ? (r.note.empty() ? "ok" : "ok (" + r.note + ")")
                              : "FAIL: " + r.failure);
    return s;
}

} // namespace fird
