// Diagnostics of the fast path: given rays and their first hits, per-bounce walk
// profiles, reflections per texel, and ray paths traced bounce by bounce.
#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

FastRun FastTracer::run_rays(const std::vector<Ray>& rays, std::vector<glm::dvec4>* hits) {
    if (!current_.reflector) throw std::logic_error("FastTracer::run_rays: no reflector set");
    if (rays.size() > batch_capacity_)
        throw std::invalid_argument("run_rays: more rays than one batch holds");
    FastRun run = new_run(rays.size());
    run.heightfield_reused = !state().heightfield_dirty;
    run.timings.heightfield_ms += rasterize_mesh();
    // Upload all rays (the caller chose them; none are discarded here), in the frame; ray
    // i is emission index i (its finish's draws: material.h).
    std::vector<float> packed(rays.size() * 8, 0.0f);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            packed[i * 8 + k] = float(rays[i].origin[k] - origin_[k]);
            packed[i * 8 + 4 + k] = float(rays[i].direction[k]);
        }
        const auto index = std::uint32_t(i);
        std::memcpy(&packed[i * 8 + 3], &index, 4);
    }
    vk::Buffer uploaded(*ctx_, std::max<std::size_t>(rays.size(), 1) * kRayBytes, vk::kStorageUsage,
                        vk::MemoryUse::Device, "fird.rays.uploaded");
    uploaded.upload(*ctx_, std::span<const float>(packed));
    if (hits)
        hits_ = vk::Buffer(*ctx_, std::max<std::size_t>(rays.size(), 1) * 32, vk::kStorageUsage,
                           vk::MemoryUse::Readback, "fird.hits");
    submit(&run.timings.trace_ms, [&](VkCommandBuffer cb) {
        if (state().heightfield_dirty) record_heightfield(cb, run);
        record_run_start(cb, false);
        record_batch_start(cb, rays.size(), rays.size());
        record_bounces(cb, uploaded, 0, run, hits != nullptr);
        record_to_lm(cb, run);
        record_batch_end(cb);
    });
    state().heightfield_dirty = false;
    tally_batch(run);
    finish(run);
    if (hits) {
        const auto both = hits_.download_as<glm::vec4>(*ctx_, 2 * rays.size());
        hits->resize(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const glm::vec4 h = both[2 * i];
            (*hits)[i] = h.w < 0.0f ? glm::dvec4(h) : glm::dvec4(glm::dvec3(h) + origin_, h.w);
        }
        hits_ = vk::Buffer(*ctx_, 32, vk::kStorageUsage, vk::MemoryUse::Device, "fird.hits.unused");
    }
    return run;
}

void FastTracer::set_profile(bool on) {
    if (on == trace_profile_pipeline_.has_value()) return;
    if (!on) {
        trace_profile_pipeline_.reset();
        profile_ =
            vk::Buffer(*ctx_, 16, vk::kStorageUsage, vk::MemoryUse::Device, "fird.profile.unused");
        return;
    }
    trace_profile_pipeline_.emplace(
        trace_pipeline(*ctx_, spec_, {FIRD_SPEC_PROFILE}, "fird.trace.profile"));
    profile_ = vk::Buffer(*ctx_, (FIRD_MAX_REFLECTIONS + 2) * gpu::kProfileFields * 4,
                          vk::kStorageUsage, vk::MemoryUse::Readback, "fird.profile");
}

void FastTracer::read_profile(FastRun& run) const {
    const auto* p = static_cast<const std::uint32_t*>(profile_.data());
    for (std::size_t b = 0; b < run.bounces.size(); ++b) {
        const std::uint32_t* f = p + b * gpu::kProfileFields;
        run.bounces[b].steps = wide(f + gpu::kProfileSteps);
        run.bounces[b].lane_steps = wide(f + gpu::kProfileLaneSteps);
        run.bounces[b].leaf_tests = wide(f + gpu::kProfileLeafTests);
        run.bounces[b].lane_leaf_tests = wide(f + gpu::kProfileLaneLeafTests);
    }
}

void FastTracer::set_count_texel_hits(bool on) {
    count_texel_hits_ = on;
    const std::uint64_t bytes = on ? std::uint64_t(params_.hf_w) * params_.hf_h * 8 : 16;
    // Device-local: the trace adds to it atomically; read_texel_hits copies it out.
    texel_hits_ =
        vk::Buffer(*ctx_, bytes, vk::kStorageUsage, vk::MemoryUse::Device, "fird.texel_hits");
}

TexelHits FastTracer::read_texel_hits() const {
    if (!count_texel_hits_) throw std::logic_error("FastTracer: texel hits are not counted");
    const std::size_t n = std::size_t(params_.hf_w) * params_.hf_h;
    const auto all = texel_hits_.download_as<std::uint32_t>(*ctx_, 2 * n);
    return {params_.hf_w,
            params_.hf_h,
            {all.begin(), all.begin() + std::ptrdiff_t(n)},
            {all.begin() + std::ptrdiff_t(n), all.end()}};
}

std::vector<RayPath> FastTracer::trace_paths(const std::vector<Ray>& rays, std::size_t pick,
                                             std::vector<WalkStep>* walk, std::uint64_t first_index,
                                             const std::vector<std::uint64_t>* indices) {
    if (indices && (indices->size() != rays.size() ||
                    std::any_of(indices->begin(), indices->end(),
                                [](std::uint64_t i) { return i >> 32 != 0; })))
        throw std::invalid_argument("trace_paths: one index below 2^32 per ray");
    if (indices) first_index = 0; // each ray's own index, its high word 0
    if (!current_.reflector) throw std::logic_error("FastTracer::trace_paths: no reflector set");
    if (rays.size() > batch_capacity_)
        throw std::invalid_argument("trace_paths: more rays than one batch holds");
    FastRun unused;
    build_heightfield(unused);
    const std::size_t n = rays.size();
    std::vector<RayPath> paths(n);
    struct Live {
        std::size_t path;
        glm::vec3 origin, direction;
        std::uint32_t texel;
    };
    std::vector<Live> live;
    for (std::size_t i = 0; i < n; ++i) {
        paths[i].vertices.push_back(rays[i].origin);
        live.push_back({i, glm::vec3(rays[i].origin - origin_), glm::vec3(rays[i].direction), 0});
    }
    // Scratch so that the run's far field and counters are left as they are.
    const std::size_t slots = std::max<std::size_t>(n, 1);
    vk::Buffer in(*ctx_, slots * kRayBytes, vk::kStorageUsage, vk::MemoryUse::Upload,
                  "fird.paths.in");
    vk::Buffer out(*ctx_, slots * kRayBytes, vk::kStorageUsage, vk::MemoryUse::Device,
                   "fird.paths.out");
    vk::Buffer counters(*ctx_, kCountersBytes, vk::kStorageUsage, vk::MemoryUse::Device,
                        "fird.paths.counters");
    vk::Buffer farfield(*ctx_, std::uint64_t(farfield_cells()) * 4 * params_.farfield_layers,
                        vk::kStorageUsage, vk::MemoryUse::Device, "fird.paths.farfield");
    vk::Buffer kept_hits = std::move(hits_);
    hits_ = vk::Buffer(*ctx_, slots * 32, vk::kStorageUsage, vk::MemoryUse::Readback,
                       "fird.paths.hits");
    const bool record = walk != nullptr && pick < n;
    vk::Buffer kept_walk;
    if (record) {
        if (!trace_walk_pipeline_) {
            trace_walk_pipeline_.emplace(trace_pipeline(
                *ctx_, spec_, {FIRD_SPEC_RECORD_WALK, FIRD_SPEC_DIAGNOSTICS}, "fird.trace.walk"));
        }
        kept_walk = std::move(walk_);
        walk_ =
            vk::Buffer(*ctx_, (1 + gpu::kWalkStepVec4s * std::uint64_t(gpu::kWalkCapacity)) * 16,
                       vk::kStorageUsage, vk::MemoryUse::Readback, "fird.walk");
        walk->clear();
    }
    // One bounce per submission, as the fast path traces them: a reflection's ray
    // starts at its hit, skipping the texel it left (direction.w carries it; origin.w the
    // ray's emission index, its place in `rays`).
    for (std::uint32_t bounce = 0; bounce < params_.max_bounces && !live.empty(); ++bounce) {
        std::vector<float> packed(live.size() * 8, 0.0f);
        for (std::size_t k = 0; k < live.size(); ++k) {
            const Live& l = live[k];
            for (int c = 0; c < 3; ++c) {
                packed[k * 8 + c] = l.origin[c];
                packed[k * 8 + 4 + c] = l.direction[c];
            }
            const auto index = std::uint32_t(indices ? (*indices)[l.path] : first_index + l.path);
            std::memcpy(&packed[k * 8 + 3], &index, 4);
            if (bounce > 0) {
                const std::uint32_t texel_bits =
                    (l.texel % params_.hf_w) | ((l.texel / params_.hf_w) << 16);
                std::memcpy(&packed[k * 8 + 7], &texel_bits, 4);
            }
        }
        in.upload(*ctx_, std::span<const float>(packed));
        // The picked ray's place in this bounce's input (none once it has left).
        std::uint32_t walk_ray = ~0u;
        for (std::size_t k = 0; k < live.size(); ++k)
            if (live[k].path == pick) walk_ray = std::uint32_t(k);
        const bool walking = record && walk_ray != ~0u;
        ctx_->submit_and_wait([&](VkCommandBuffer cb) {
            vkCmdFillBuffer(cb, counters.get(), 0, VK_WHOLE_SIZE, 0);
            if (walking) vkCmdFillBuffer(cb, walk_.get(), 0, 16, 0);
            // The count the trace reads (the run's loop state is not needed after its run).
            vkCmdFillBuffer(cb, loop_.get(), gpu::kLoopActive * 4, 4, std::uint32_t(live.size()));
            vk::barrier_all(cb);
            const gpu::TracePush push{.first_lo = std::uint32_t(first_index),
                                      .first_hi = std::uint32_t(first_index >> 32),
                                      .bounce = bounce,
                                      .record_hits = 1u,
                                      .walk_ray = walk_ray};
            dispatch_trace(cb, in, out, counters, farfield, push, walking,
                           groups(live.size(), FIRD_TRACE_WORKGROUP_SIZE));
        });
        if (walking) {
            const auto* w = static_cast<const glm::vec4*>(walk_.data());
            const auto steps = std::min<std::uint32_t>(std::uint32_t(w[0].x), gpu::kWalkCapacity);
            // Heights out of the device's frame (relative to origin_) into the scene's.
            const auto z = [&](float device_z) { return float(double(device_z) + origin_.z); };
            for (std::uint32_t k = 0; k < steps; ++k) {
                const glm::vec4* r = &w[1 + gpu::kWalkStepVec4s * k];
                walk->push_back({.bounce = bounce,
                                 .level = std::uint32_t(r[0].x),
                                 .x = std::uint32_t(r[0].y),
                                 .y = std::uint32_t(r[0].z),
                                 .max_height_mm = z(r[0].w),
                                 .t = r[1].x,
                                 .t_exit = r[1].y,
                                 .ray_z_mm = z(r[1].z),
                                 .ray_z_exit_mm = z(r[1].w),
                                 .decision = WalkDecision(std::uint32_t(r[2].x)),
                                 .t_next = r[2].y});
            }
        }
        const auto hits = hits_.download_as<glm::vec4>(*ctx_, 2 * live.size());
        std::vector<Live> next;
        for (std::size_t k = 0; k < live.size(); ++k) {
            RayPath& path = paths[live[k].path];
            if (hits[2 * k].w < 0.0f) continue; // it leaves with its current direction
            const glm::vec3 p(hits[2 * k]);
            const glm::vec3 r(hits[2 * k + 1]);
            std::uint32_t texel = 0;
            std::memcpy(&texel, &hits[2 * k + 1].w, 4);
            path.vertices.push_back(glm::dvec3(p) + origin_);
            ++path.reflections;
            next.push_back({live[k].path, p, r, texel});
        }
        for (Live& l : next)
            paths[l.path].direction = glm::dvec3(l.direction);
        live = std::move(next);
    }
    hits_ = std::move(kept_hits);
    if (record) walk_ = std::move(kept_walk);
    // Each path ends with its segment leaving the holder box.
    for (std::size_t i = 0; i < n; ++i) {
        RayPath& path = paths[i];
        if (path.reflections == 0) path.direction = rays[i].direction;
        const Ray last{path.vertices.back(), glm::normalize(path.direction)};
        double t0 = 0.0, t1 = 0.0;
        const bool inside = clip_to_box(last, scene_.holder.min_mm, scene_.holder.max_mm, t0, t1);
        path.vertices.push_back(last.origin + (inside ? t1 : 0.0) * last.direction);
    }
    return paths;
}

} // namespace fird
