// Diagnostics of the fast path: given rays and their first hits, per-bounce walk
// profiles, reflections per texel, and ray paths followed through the bounce loop.
#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

namespace {

// A member buffer swapped for scratch, put back when the scope ends however it ends.
struct SwappedBuffer {
    vk::Buffer& slot;
    vk::Buffer kept;
    SwappedBuffer(vk::Buffer& member, vk::Buffer scratch)
        : slot(member), kept(std::exchange(member, std::move(scratch))) {}
    SwappedBuffer(const SwappedBuffer&) = delete;
    SwappedBuffer& operator=(const SwappedBuffer&) = delete;
    ~SwappedBuffer() { slot = std::move(kept); }
};

} // namespace

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
    RayTable uploaded =
        make_ray_table(*ctx_, rays.size(), vk::MemoryUse::Device, "fird.rays.uploaded");
    uploaded.rays.upload(*ctx_, std::span<const float>(packed));
    if (hits)
        hits_ = vk::Buffer(*ctx_, std::max<std::size_t>(rays.size(), 1) * kHitRecordBytes,
                           vk::kStorageUsage, vk::MemoryUse::Readback, "fird.hits");
    submit(&run.timings.trace_ms, [&](VkCommandBuffer cb) {
        if (state().heightfield_dirty) record_heightfield(cb, run);
        record_run_start(cb, false);
        record_batch_start(cb, rays.size(), rays.size());
        record_bounces(cb, uploaded, 0, run,
                       {.hits = hits ? BounceRecording::Hits::First : BounceRecording::Hits::None});
        record_to_lm(cb, run);
        record_batch_end(cb);
    });
    state().heightfield_dirty = false;
    tally_batch(run);
    finish(run);
    if (hits) {
        const auto records = hits_.download_as<glm::vec4>(*ctx_, kHitRecordVec4s * rays.size());
        hits->resize(rays.size());
        for (std::size_t i = 0; i < rays.size(); ++i) {
            const glm::vec4 h = records[kHitRecordVec4s * i];
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
    const std::size_t n = rays.size();
    // Ray i carries its emission index's low word (origin.w), as the rayset's rays do.
    const auto carried = [&](std::size_t i) {
        return std::uint32_t(indices ? (*indices)[i] : first_index + i);
    };
    const bool record = walk != nullptr && pick < n;
    if (record) {
        // The walk is recorded for the ray carrying the pick's index, whatever its slot.
        const std::uint32_t picked = carried(pick);
        for (std::size_t i = 0; i < n; ++i)
            if (i != pick && carried(i) == picked)
                throw std::invalid_argument(fmt::format(
                    "trace_paths: rays {} and {} carry the same index {}, so the walk of ray {} "
                    "cannot be told apart",
                    pick, i, picked, pick));
        walk->clear();
        if (!trace_walk_pipeline_) {
            trace_walk_pipeline_.emplace(trace_pipeline(
                *ctx_, spec_, {FIRD_SPEC_RECORD_WALK, FIRD_SPEC_DIAGNOSTICS}, "fird.trace.walk"));
        }
    }
    FastRun run = new_run(n);
    run.timings.heightfield_ms += rasterize_mesh();
    std::vector<float> packed(std::max<std::size_t>(n, 1) * 8, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            packed[i * 8 + k] = float(rays[i].origin[k] - origin_[k]);
            packed[i * 8 + 4 + k] = float(rays[i].direction[k]);
        }
        const std::uint32_t index = carried(i);
        std::memcpy(&packed[i * 8 + 3], &index, 4);
    }
    RayTable uploaded = make_ray_table(*ctx_, n, vk::MemoryUse::Upload, "fird.paths.rays");
    uploaded.rays.upload(*ctx_, std::span<const float>(packed));
    // A record per ray and bounce (the strict policy's final check included), and a walk
    // region per bounce, in scratch that stands in for the run's own buffers until the
    // paths are read (put back however this ends).
    const std::uint32_t bounces = passes();
    const std::size_t slots = std::max<std::size_t>(n, 1);
    const std::uint64_t record_bytes = bounces * slots * kHitRecordBytes;
    if (record_bytes > ctx_->limits().max_storage_buffer_range)
        throw std::invalid_argument(fmt::format(
            "trace_paths: {} rays x {} bounces of hit records take {} bytes, more than the "
            "device's largest storage buffer ({} bytes)",
            n, bounces, record_bytes, ctx_->limits().max_storage_buffer_range));
    const std::uint64_t walk_region = 1 + gpu::kWalkStepVec4s * std::uint64_t(gpu::kWalkCapacity);
    const SwappedBuffer paths_hits(hits_, vk::Buffer(*ctx_, record_bytes, vk::kStorageUsage,
                                                     vk::MemoryUse::Readback, "fird.paths.hits"));
    std::optional<SwappedBuffer> paths_walk;
    if (record)
        paths_walk.emplace(walk_, vk::Buffer(*ctx_, bounces * walk_region * 16, vk::kStorageUsage,
                                             vk::MemoryUse::Readback, "fird.walk"));
    // The bounce loop of every run, its far field counts and counters the run's scratch
    // (cleared by the next run's start, never read back here).
    submit(&run.timings.trace_ms, [&](VkCommandBuffer cb) {
        if (state().heightfield_dirty) record_heightfield(cb, run);
        if (record) vkCmdFillBuffer(cb, walk_.get(), 0, VK_WHOLE_SIZE, 0);
        record_batch_start(cb, n, n);
        record_bounces(cb, uploaded, first_index, run,
                       {.hits = BounceRecording::Hits::Every,
                        .rays = std::uint32_t(slots),
                        .walk_index = record ? std::optional(carried(pick)) : std::nullopt});
    });
    state().heightfield_dirty = false;
    const auto records = hits_.download_as<glm::vec4>(*ctx_, kHitRecordVec4s * bounces * slots);
    // Each path followed from bounce to bounce by its record's next slot.
    std::vector<RayPath> paths(n);
    for (std::size_t i = 0; i < n; ++i) {
        RayPath& path = paths[i];
        path.vertices.push_back(rays[i].origin);
        std::size_t slot = i;
        for (std::uint32_t bounce = 0; bounce < params_.max_bounces; ++bounce) {
            const glm::vec4* r = &records[kHitRecordVec4s * (bounce * slots + slot)];
            if (r[0].w < 0.0f) break; // it leaves with its current direction
            path.vertices.push_back(glm::dvec3(r[0]) + origin_);
            path.direction = glm::dvec3(r[1]);
            ++path.reflections;
            std::uint32_t next = 0;
            std::memcpy(&next, &r[2].x, 4);
            if (next == 0) break; // it left the reflector with this direction
            slot = next - 1;
        }
    }
    if (record) {
        const auto* w = static_cast<const glm::vec4*>(walk_.data());
        // Heights out of the device's frame (relative to origin_) into the scene's.
        const auto z = [&](float device_z) { return float(double(device_z) + origin_.z); };
        for (std::uint32_t bounce = 0; bounce < params_.max_bounces; ++bounce) {
            const glm::vec4* region = w + bounce * walk_region;
            const auto steps =
                std::min<std::uint32_t>(std::uint32_t(region[0].x), gpu::kWalkCapacity);
            for (std::uint32_t k = 0; k < steps; ++k) {
                const glm::vec4* r = &region[1 + gpu::kWalkStepVec4s * k];
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
    }
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
