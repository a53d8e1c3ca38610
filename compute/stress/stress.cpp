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

double largest(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end());
}

bool finite(const glm::dvec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The shares of rays whose fate may differ from the reference's (tunnelled, spurious, an
// extra or a missing reflection):
// - near a clamp plane (within clamp_band_mm of the holder's top or floor): a ray that
//   leaves past the rim closer than the band can miss the rim's last sliver, or meet a
//   patch that cut the corner. The band (<= 0.03 mm for these cases) over the cups' 3-4 mm
//   rim radius is ~1 % of their opening: 1.5 % bounds it (measured: 3-10 of 2000);
// - elsewhere: after several bounces a hit displaced by a fraction of a texel can cross a
//   kink (the flutes' apex, the rim) that the reference's does not; each bounce multiplies
//   the displacement, so such rays are a few in a thousand on 5-6 bounces (0-4 of 2000
//   measured) and none on one bounce. 0.5 % (10 rays) bounds them; a systematic fault (a
//   self-hit, a leak through texel edges) affects far more.
constexpr double kMaxMismatchesNearClamp = 0.015, kMaxMismatchesElsewhere = 0.005;
// Rays whose leaving direction errs by more than the case's tolerance: those whose fate
// differs (at most 2 % above) and those whose hits on either side lie on two sides of a
// kink (the flutes' apex, the rim), a share of the order of the kinks' band after several
// bounces (15 of 2000 on the fluted cup, 0-2 elsewhere): 2.5 % in all.
constexpr double kMaxDirectionOutliers = 0.025;

// How far the refined surface may stand from the true one where the holder clamps it: a
// texel's bilinear patch across the kink between a wall of slope m and the flat clamp
// plane cuts the corner by up to m times a quarter of the texel's diagonal. Rays whose
// fate turns on a hit that close to a clamp plane may go either way.
double clamp_band_mm(const Surface& surface, const Scene& s) {
    const Holder& h = s.holder;
    const std::uint32_t w = s.trace.heightfield_w, ht = s.trace.heightfield_h;
    const double tx = (h.max_mm.x - h.min_mm.x) / w, ty = (h.max_mm.y - h.min_mm.y) / ht;
    // The slope on a grid of at most 256 x 256 texel centres (a bound, not an integral).
    const std::uint32_t step_x = std::max(1u, w / 256), step_y = std::max(1u, ht / 256);
    double slope = 0.0;
    for (std::uint32_t j = 0; j < ht; j += step_y)
        for (std::uint32_t i = 0; i < w; i += step_x) {
            const double x = h.min_mm.x + (i + 0.5) * tx, y = h.min_mm.y + (j + 0.5) * ty;
            const glm::dvec2 g = surface.raw_gradient(x, y);
            if (std::isfinite(g.x) && std::isfinite(g.y)) slope = std::max(slope, glm::length(g));
        }
    return slope * std::hypot(tx, ty) / 4.0;
}

// Whether a hit at height z lies within `band` of one of the holder's clamp planes.
bool near_clamp(const Holder& h, double z, double band) {
    return std::abs(z - h.max_mm.z) <= band || std::abs(z - h.min_mm.z) <= band;
}

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
    std::vector<glm::dvec4> hits;
    const FastRun first = fast.run_rays(rays, &hits);
    r.aborted += first.aborted;
    const double band = clamp_band_mm(surface, s);
    std::uint64_t first_near_clamp = 0, path_near_clamp = 0; // mismatches within the band
    const double tx = (s.holder.max_mm.x - s.holder.min_mm.x) / s.trace.heightfield_w;
    const double ty = (s.holder.max_mm.y - s.holder.min_mm.y) / s.trace.heightfield_h;
    std::vector<double> errors;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const glm::dvec4 h = hits[i];
        if (!std::isfinite(h.x) || !std::isfinite(h.y) || !std::isfinite(h.z) ||
            !std::isfinite(h.w))
            ++r.nonfinite;
        const SurfaceHit ref = first_surface_hit(surface, rays[i], 0.0);
        const bool fast_hit = h.w >= 0.0, ref_hit = ref.t.has_value();
        if (ref_hit && !fast_hit) {
            ++r.tunnelled;
            const glm::dvec3 p = rays[i].origin + *ref.t * rays[i].direction;
            if (near_clamp(s.holder, p.z, band)) ++first_near_clamp;
            if (std::getenv("FIRD_STRESS_DEBUG"))
                std::fprintf(stderr,
                             "tunnelled: o (%.9g, %.9g, %.9g) d (%.9g, %.9g, %.9g) ref t %.9g\n",
                             rays[i].origin.x, rays[i].origin.y, rays[i].origin.z,
                             rays[i].direction.x, rays[i].direction.y, rays[i].direction.z, *ref.t);
        }
        if (fast_hit && !ref_hit && ref.start == HitStart::Above) {
            ++r.spurious;
            if (near_clamp(s.holder, h.z, band)) ++first_near_clamp;
        }
        if (fast_hit && ref_hit) {
            const glm::dvec3 p = rays[i].origin + *ref.t * rays[i].direction;
            errors.push_back(std::max(std::abs(h.x - p.x) / tx, std::abs(h.y - p.y) / ty));
        }
    }
    r.hit_error_p99_texels = p99(errors);
    r.hit_error_max_texels = largest(errors);

    // Whole paths: reflections and leaving directions against the reference's.
    const auto paths = fast.trace_paths(rays);
    std::vector<double> angles;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        for (const glm::dvec3& v : paths[i].vertices)
            if (!finite(v)) ++r.nonfinite;
        std::vector<glm::dvec3> ref_vertices;
        // The finish's draws of ray i (trace_paths keys ray i on index i).
        const RayFinish finish{.material = s.reflector.material, .seed = s.trace.seed, .index = i};
        const PathResult ref = trace_path(surface, s.holder, rays[i], s.trace.max_bounces,
                                          s.trace.bounce_policy, &ref_vertices, &finish);
        if (ref.fate == RayFate::Lost || ref.fate == RayFate::BelowSurface) continue;
        // vertices: the origin, then hit k at [k] (the fast path's and the reference's).
        if (paths[i].reflections > ref.reflections) {
            ++r.extra_reflections;
            if (near_clamp(s.holder, paths[i].vertices[ref.reflections + 1].z, band))
                ++path_near_clamp;
        }
        if (paths[i].reflections < ref.reflections) {
            ++r.missing_reflections;
            if (near_clamp(s.holder, ref_vertices[paths[i].reflections + 1].z, band))
                ++path_near_clamp;
            if (std::getenv("FIRD_STRESS_DEBUG")) {
                std::fprintf(stderr, "missing: o (%.9g, %.9g, %.9g) d (%.9g, %.9g, %.9g)\n",
                             rays[i].origin.x, rays[i].origin.y, rays[i].origin.z,
                             rays[i].direction.x, rays[i].direction.y, rays[i].direction.z);
                for (const auto& p : ref_vertices)
                    std::fprintf(stderr, "  ref  %.7f %.7f %.7f\n", p.x, p.y, p.z);
                for (const auto& p : paths[i].vertices)
                    std::fprintf(stderr, "  fast %.7f %.7f %.7f\n", p.x, p.y, p.z);
            }
        }
        if (paths[i].reflections > 0 || ref.reflections > 0)
            angles.push_back(std::acos(std::clamp(
                glm::dot(glm::normalize(paths[i].direction), glm::normalize(ref.direction)), -1.0,
                1.0)));
    }
    r.direction_error_p99_rad = p99(angles);
    r.direction_error_max_rad = largest(angles);
    r.direction_outliers = std::uint64_t(std::count_if(
        angles.begin(), angles.end(), [&](double a) { return a > c.direction_tolerance_rad; }));
    r.mismatches_near_clamp = first_near_clamp + path_near_clamp;

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
    // Rays whose fate differs from the reference's, near a clamp plane and elsewhere (the
    // paths' only where they are compared).
    const bool compare_paths = c.compare_surface && c.compare_paths;
    const std::uint64_t near = first_near_clamp + (compare_paths ? path_near_clamp : 0);
    const std::uint64_t all = r.tunnelled + r.spurious +
                              (compare_paths ? r.extra_reflections + r.missing_reflections : 0);
    if (c.compare_surface) {
        if (double(near) > kMaxMismatchesNearClamp * n)
            fail(fmt::format("{} rays change fate within {:.2g} mm of a clamp plane", near, band));
        if (double(all - near) > kMaxMismatchesElsewhere * n)
            fail(fmt::format("{} rays change fate (tunnelled, spurious, extra or missing "
                             "reflections) away from the clamp planes",
                             all - near));
        if (r.hit_error_p99_texels > c.hit_tolerance_texels)
            fail(fmt::format("hit error p99 {:.3g} texels > {:.3g}", r.hit_error_p99_texels,
                             c.hit_tolerance_texels));
    }
    if (compare_paths && double(r.direction_outliers) > kMaxDirectionOutliers * n)
        fail(fmt::format("{} leaving directions off by more than {:.3g} rad", r.direction_outliers,
                         c.direction_tolerance_rad));
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
                         {"missing_reflections", r.missing_reflections},
                         {"mismatches_near_clamp", r.mismatches_near_clamp},
                         {"direction_outliers", r.direction_outliers},
                         {"hit_error_p99_texels", r.hit_error_p99_texels},
                         {"hit_error_max_texels", r.hit_error_max_texels},
                         {"direction_error_p99_rad", r.direction_error_p99_rad},
                         {"direction_error_max_rad", r.direction_error_max_rad},
                         {"energy_balanced", r.energy_balanced},
                         {"ok", r.ok},
                         {"failure", r.failure},
                         {"note", r.note}});
    }
    return {{"cases", cases}, {"ok", ok}};
}

std::string stress_table(const std::vector<StressResult>& results) {
    std::string s = fmt::format(
        "{:<52} {:>5} {:>5} {:>4} {:>6} {:>5} {:>5} {:>5} {:>5} {:>9} {:>9} {:>9} {:>9}  {}\n",
        "case", "rays", "abort", "NaN", "tunnel", "spur", "extra", "miss", "clamp", "hit p99",
        "hit max", "dir p99", "dir max", "result");
    s += fmt::format(
        "{:<52} {:>5} {:>5} {:>4} {:>6} {:>5} {:>5} {:>5} {:>5} {:>9} {:>9} {:>9} {:>9}\n", "", "",
        "", "", "", "", "", "", "", "texels", "texels", "rad", "rad");
    for (const StressResult& r : results)
        s += fmt::format(
            "{:<52} {:>5} {:>5} {:>4} {:>6} {:>5} {:>5} {:>5} {:>5} {:>9.3g} {:>9.3g} "
            "{:>9.3g} {:>9.3g}  {}\n",
            r.name, r.rays, r.aborted, r.nonfinite, r.tunnelled, r.spurious, r.extra_reflections,
            r.missing_reflections, r.mismatches_near_clamp, r.hit_error_p99_texels,
            r.hit_error_max_texels, r.direction_error_p99_rad, r.direction_error_max_rad,
            r.ok ? (r.note.empty() ? "ok" : "ok (" + r.note + ")") : "FAIL: " + r.failure);
    return s;
}

} // namespace fird
