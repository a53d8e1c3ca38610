// The rayset pass (the source's rays, the effective ones appended) and the ordering of
// rays by direction (bucket counts, scan, scatter) that the rayset and each bounce use.
#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "model/ray_file_source.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

void FastTracer::record_rayset(VkCommandBuffer cb, std::uint64_t first, std::uint64_t n,
                               const RayTable& rays, FastRun& run) {
    if (!rayset_ordered_at_birth()) {
        vkCmdFillBuffer(cb, order_buckets_.get(), 0, VK_WHOLE_SIZE, 0);
        vk::barrier_all(cb);
    }
    timed(cb, &run.timings.rayset_ms, nullptr, [&] {
        const passes::RaysetBindings b{.params = vk::uniform(state().params_buffer),
                                       .rays = vk::storage_texel(rays.texels),
                                       .counters = vk::storage(counters_),
                                       .buckets = vk::storage(order_buckets_),
                                       .emitter_table =
                                           vk::storage_texel(emitter_table_for(first).texels)};
        const gpu::RaysetPush push{
            .first_lo = std::uint32_t(first),
            .first_hi = std::uint32_t(first >> 32),
            .count = std::uint32_t(n),
            // Direct light binned: the rays that miss the holder
            // are traced too, and leave as direct light.
            .keep_all = skips_.discard_before_trace && params_.bin_direct == 0u ? 0u : 1u};
        rayset_pipeline_.dispatch(cb, b, push, groups(n, FIRD_RAYSET_WORKGROUP_SIZE));
    });
    vk::barrier_all(cb);
}

const FloatTable& FastTracer::emitter_table_for(std::uint64_t first) const {
    if (scene_.source.kind != SourceKind::RayFile) return emitter_table_;
    return ray_file_tables_[(first / batch_capacity_) % 2];
}

void FastTracer::read_ray_file_batch(std::uint64_t first, std::uint64_t n) const {
    const std::uint64_t seed =
        std::uint64_t(params_.seed_lo) | (std::uint64_t(params_.seed_hi) << 32);
    auto* const table = static_cast<float*>(emitter_table_for(first).values.data());
    // Emissions [from, to), placed in double, then made relative to the frame's origin and
    // rounded to float, into their slots of the batch.
    const auto read = [&](std::uint64_t from, std::uint64_t to) {
        float* out = table + (from - first) * gpu::kRayFileFloats;
        emit_ray_file_rays(scene_.source, seed, from, to - from, scene_.trace.rays,
                           [&](const Ray& r) {
                               const glm::dvec3 o = r.origin - origin_;
                               *out++ = float(o.x);
                               *out++ = float(o.y);
                               *out++ = float(o.z);
                               *out++ = float(r.direction.x);
                               *out++ = float(r.direction.y);
                               *out++ = float(r.direction.z);
                           });
    };
    // The batch is read in parts at once (up to 8), a thread and a reader each (the
    // emissions do not depend on how they are split).
    const std::uint64_t parts = std::clamp<std::uint64_t>(
        std::min<std::uint64_t>(std::thread::hardware_concurrency(), 8), 1, n / 65536 + 1);
    std::vector<std::thread> helpers;
    std::exception_ptr failure;
    std::mutex failure_mutex;
    for (std::uint64_t k = 1; k < parts; ++k)
        helpers.emplace_back([&, k] {
            try {
                read(first + n * k / parts, first + n * (k + 1) / parts);
            } catch (...) {
                const std::lock_guard lock(failure_mutex);
                failure = std::current_exception();
            }
        });
    try {
        read(first, first + n / parts);
    } catch (...) {
        const std::lock_guard lock(failure_mutex);
        failure = std::current_exception();
    }
    for (std::thread& t : helpers)
        t.join();
    if (failure) std::rethrow_exception(failure);
}

void FastTracer::record_bounce_args(VkCommandBuffer cb, std::uint32_t stage, std::uint32_t bounce) {
    const passes::BounceArgsBindings b{.counters = vk::storage(counters_),
                                       .loop = vk::storage(loop_)};
    const gpu::BounceArgsPush push{.stage = stage,
                                   .bounce = bounce,
                                   .trace_empty = skips_.skip_empty_bounces ? 0u : 1u,
                                   .groups_max = ctx_->limits().max_workgroup_count[0]};
    bounce_args_pipeline_.dispatch(cb, b, push, 1);
    vk::barrier_all(cb);
}

void FastTracer::record_order(VkCommandBuffer cb, const RayTable& from, const RayTable& to,
                              bool reflected) {
    bucket_scan_pipeline_.dispatch_indirect(cb, {.buckets = vk::storage(order_buckets_)}, {}, loop_,
                                            gpu::kLoopScanArgs * 4);
    vk::barrier_all(cb);
    const passes::OrderBindings b{.params = vk::uniform(state().params_buffer),
                                  .rays_in = vk::storage_texel(from.texels),
                                  .rays_out = vk::storage_texel(to.texels),
                                  .buckets = vk::storage(order_buckets_),
                                  .loop = vk::storage(loop_)};
    const gpu::RaysetOrderPush push{.reflected = reflected ? 1u : 0u};
    order_pipeline_.dispatch_indirect(cb, b, push, loop_, gpu::kLoopOrderArgs * 4);
    vk::barrier_all(cb);
}

void FastTracer::record_rayset_order(VkCommandBuffer cb, const RayTable& from, const RayTable& to,
                                     FastRun& run) {
    timed(cb, &run.timings.rayset_ms, nullptr, [&] {
        record_bounce_args(cb, gpu::kArgsOrderRayset, 0);
        record_order(cb, from, to, false);
    });
}

std::vector<Ray> FastTracer::rayset() const {
    if (rayset_chunks_.size() * batch_capacity_ < scene_.trace.rays)
        throw std::logic_error("FastTracer::rayset: no rayset kept");
    std::vector<Ray> rays;
    for (const RaysetChunk& chunk : rayset_chunks_) {
        const auto packed = chunk.rays.rays.download_as<float>(*ctx_, chunk.effective * 8);
        for (std::size_t i = 0; i < chunk.effective; ++i) {
            const float* r = &packed[i * 8];
            rays.push_back(Ray{glm::dvec3(r[0], r[1], r[2]) + origin_, {r[4], r[5], r[6]}});
        }
    }
    return rays;
}

} // namespace fird
