#include "reference_tracer.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "material.h"
#include "model/ray_file_source.hpp"
#include "sampling/philox.hpp"
#include "surface_hit.hpp"

namespace fird {

namespace {
// After a reflection the search starts this far along the new direction: the
// reflected ray leaves the surface, so this only skips the hit it starts on.
constexpr double kBounceOffset_mm = 1e-7;
constexpr std::uint64_t kBlock = 1u << 14;
} // namespace

PathResult trace_path(const Surface& surface, const Holder& holder, const Ray& ray,
                      std::uint32_t max_bounces, BouncePolicy policy,
                      std::vector<glm::dvec3>* vertices, const RayFinish* finish) {
    const double spread_rad = finish ? glm::radians(finish->material.spread_deg) : 0.0;
    const std::uint32_t lobe =
        finish && finish->material.lobe == SpreadLobe::Phong ? gpu::kLobePhong : gpu::kLobeGaussian;
    if (vertices) vertices->assign(1, ray.origin);
    if (!ray_meets_box(ray, holder)) return {RayFate::Discarded, 0, ray.direction};
    Ray r = ray;
    std::uint32_t reflections = 0;
    for (;;) {
        const double t_min = reflections == 0 ? 0.0 : kBounceOffset_mm;
        const SurfaceHit hit = first_surface_hit(surface, r, t_min);
        if (hit.start == HitStart::BelowSurface)
            return {RayFate::BelowSurface, reflections, r.direction};
        if (hit.start == HitStart::Blocked) return {RayFate::Lost, reflections, r.direction};
        if (!hit.t) {
            if (vertices) vertices->push_back(r.origin + 10.0 * r.direction);
            if (reflections == 0) return {RayFate::Direct, 0, r.direction};
            return {RayFate::FarField, reflections, r.direction};
        }
        if (reflections == max_bounces) {
            // Only reached under the strict policy: it would hit again.
            if (vertices) vertices->push_back(r.origin + *hit.t * r.direction);
            return {RayFate::Lost, reflections, r.direction};
        }
        const glm::dvec3 p = r.origin + *hit.t * r.direction;
        const glm::dvec3 n = surface_normal(surface, p.x, p.y);
        std::array<double, 4> u{0.5, 0.5, 0.5, 0.5};
        if (spread_rad > 0.0) // this reflection's draw: (ray index, bounce) alone
            u = philox_uniforms(finish->seed, finish->index, gpu::kMaterialStream + reflections);
        r = {p, gpu::emission::reflected_direction(r.direction, n, spread_rad, lobe, u[0], u[1])};
        ++reflections;
        if (vertices) vertices->push_back(p);
        if (reflections == max_bounces && policy == BouncePolicy::Paper) {
            // "paper": the ray leaves with its last reflected direction (Algorithm 1).
            if (vertices) vertices->push_back(p + 10.0 * r.direction);
            return {RayFate::FarField, reflections, r.direction};
        }
    }
}

ReferenceResult trace_reference(const SourceDesc& source, const Surface& surface,
                                const ReferenceOptions& o) {
    const unsigned threads =
        o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    const std::size_t cells = std::size_t(o.farfield_w) * o.farfield_h;
    // Far-field weights in rays: a ray that left after k reflections weighs R^k.
    std::vector<double> weight_by_reflections(o.max_bounces + 1, 1.0);
    for (std::size_t k = 1; k < weight_by_reflections.size(); ++k)
        weight_by_reflections[k] = weight_by_reflections[k - 1] * o.material.reflectance;
    const bool include_direct = o.direct == DirectLight::Include;
    struct Local {
        RayTally tally;
        std::vector<double> weights;
    };
    std::vector<Local> locals(threads);
    std::atomic<std::uint64_t> next{0};
    const auto start = std::chrono::steady_clock::now();
    const bool ray_file = source.kind == SourceKind::RayFile;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&](Local& local) {
        local.weights.assign(cells, 0.0);
        local.tally.by_reflections.assign(o.max_bounces + 1, 0);
        local.tally.lost_by_reflections.assign(o.max_bounces + 1, 0);
        std::vector<Ray> file_rays;
        for (;;) {
            file_rays.clear();
            const std::uint64_t begin = next.fetch_add(kBlock);
            if (begin >= o.rays) break;
            const std::uint64_t end = std::min(o.rays, begin + kBlock);
            // A ray file's block is read in one pass through the file (a read that fails,
            // a file changed since the scene was read, stops every thread and is rethrown).
            if (ray_file) {
                try {
                    emit_ray_file_rays(source, o.seed, begin, end - begin, o.rays,
                                       [&](const Ray& r) { file_rays.push_back(r); });
                } catch (...) {
                    const std::lock_guard lock(failure_mutex);
                    if (!failure) failure = std::current_exception();
                    next = o.rays;
                    break;
                }
            }
            for (std::uint64_t i = begin; i < end; ++i) {
                const Ray ray = ray_file ? file_rays[i - begin]
                                         : emit_ray(source, o.sampler, o.seed, i, o.rays);
                const RayFinish finish{.material = o.material, .seed = o.seed, .index = i};
                const PathResult path = trace_path(surface, surface.holder(), ray, o.max_bounces,
                                                   o.bounce_policy, nullptr, &finish);
                RayTally& t = local.tally;
                const auto bin = [&](double weight) {
                    local.weights[farfield_cell(path.direction, o.farfield_w, o.farfield_h)] +=
                        weight;
                };
                switch (path.fate) {
                case RayFate::Discarded:
                    // Direct light binned: a ray that misses the holder leaves as direct
                    // light (as on the fast path, which traces it then).
                    if (include_direct) {
                        ++t.direct;
                        bin(1.0);
                    } else {
                        ++t.discarded;
                    }
                    break;
                case RayFate::Direct:
                    ++t.direct;
                    if (include_direct) bin(1.0);
                    break;
                case RayFate::FarField:
                    ++t.farfield;
                    ++t.by_reflections[path.reflections];
                    bin(weight_by_reflections[path.reflections]);
                    break;
                case RayFate::BelowSurface:
                    ++t.below_surface;
                    ++t.lost;
                    ++t.lost_by_reflections[path.reflections];
                    break;
                case RayFate::Lost:
                    ++t.lost;
                    ++t.lost_by_reflections[path.reflections];
                    break;
                }
            }
        }
    };
    std::vector<std::thread> pool;
    for (unsigned k = 1; k < threads; ++k)
        pool.emplace_back(work, std::ref(locals[k]));
    work(locals[0]);
    for (auto& t : pool)
        t.join();
    if (failure) std::rethrow_exception(failure);

    ReferenceResult result;
    result.threads = threads;
    result.energy_per_ray_lm = o.rays ? source.flux_lm / double(o.rays) : 0.0;
    RayTally& total = result.tally;
    total.emitted = o.rays;
    total.by_reflections.assign(o.max_bounces + 1, 0);
    total.lost_by_reflections.assign(o.max_bounces + 1, 0);
    total.reflectance = o.material.reflectance;
    total.direct_binned = include_direct;
    std::vector<double> weights(cells, 0.0);
    for (const Local& l : locals) {
        total.discarded += l.tally.discarded;
        total.direct += l.tally.direct;
        total.farfield += l.tally.farfield;
        total.lost += l.tally.lost;
        total.below_surface += l.tally.below_surface;
        for (std::size_t b = 0; b < l.tally.by_reflections.size(); ++b) {
            total.by_reflections[b] += l.tally.by_reflections[b];
            total.lost_by_reflections[b] += l.tally.lost_by_reflections[b];
        }
        for (std::size_t c = 0; c < cells; ++c)
            weights[c] += l.weights[c];
    }
    result.farfield = FarField{o.farfield_w, o.farfield_h, std::move(weights)};
    for (double& v : result.farfield.lm)
        v *= result.energy_per_ray_lm;
    result.trace_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

} // namespace fird
