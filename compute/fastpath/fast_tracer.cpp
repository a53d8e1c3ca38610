#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "bounce_args_comp.h"
#include "bucket_scan_comp.h"
#include "counts_to_lm_comp.h"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "heightfield_comp.h"
#include "maxmip_comp.h"
#include "rayset_comp.h"
#include "rayset_order_comp.h"
#include "trace_comp.h"
#include "vk/check.hpp"
#include "walk_start_comp.h"

#include <glm/geometric.hpp>

namespace fird {

namespace {

constexpr VkDescriptorType kSB = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkDescriptorType kTB = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
constexpr std::uint64_t kRayBytes = 32;
constexpr std::uint64_t kCountersBytes = std::uint64_t(gpu::kTallyCopies) * gpu::kCounterCount * 4;
// The most device memory a kept rayset may take (1e7 emitted rays take at most 320 MB).
constexpr std::uint64_t kRaysetCacheBytes = 1ull << 30;

struct ToLmPush {
    std::uint32_t count;
    float lm_per_ray;
};

std::uint32_t groups(std::uint64_t n, std::uint32_t size) {
    return std::uint32_t((n + size - 1) / size);
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// trace.comp's bindings 0..kTraceBindLoop: uniform texel buffers at 4-6, storage else.
// `variant` lists the specialization constants (FIRD_SPEC_RECORD_WALK, _PROFILE,
// _DIAGNOSTICS) switched on over the scene's.
vk::ComputePipeline trace_pipeline(const vk::Context& ctx,
                                   std::array<std::uint32_t, FIRD_SPEC_COUNT> spec,
                                   std::initializer_list<int> variant, const char* name) {
    for (const int id : variant)
        spec[std::size_t(id)] = 1;
    return vk::ComputePipeline(
        ctx, fird_spv_trace_comp,
        {kSB, kSB, kSB, kSB, kTB, kTB, kTB, kSB, kSB, kSB, kSB, kSB, kSB, kSB, kSB, kSB},
        sizeof(gpu::TracePush), name, spec);
}

// 64-bit sums kept on the device as (low, high) pairs of uints.
std::uint64_t wide(const std::uint32_t* pair) {
    return std::uint64_t(pair[0]) | (std::uint64_t(pair[1]) << 32);
}

} // namespace

FastTracer::FastTracer(const vk::Context& ctx, const Scene& scene, std::uint64_t seed,
                       std::uint64_t max_batch_rays)
    : ctx_(&ctx), scene_(scene), origin_(fird::frame_origin(scene.holder)),
      params_(scene_params(scene, seed)), spec_(specialization(params_, scene.reflector.family)),
      rayset_pipeline_(ctx, fird_spv_rayset_comp, {kSB, kSB, kSB, kSB}, sizeof(gpu::RaysetPush),
                       "fird.rayset", spec_),
      heightfield_pipeline_(ctx, fird_spv_heightfield_comp, {kSB, kSB, kSB, kSB, kSB}, 0,
                            "fird.heightfield", spec_),
      maxmip_pipeline_(ctx, fird_spv_maxmip_comp, {kSB, kSB, kSB, kSB}, sizeof(gpu::MaxMipPush),
                       "fird.maxmip"),
      trace_pipeline_(trace_pipeline(ctx, spec_, {}, "fird.trace")),
      to_lm_pipeline_(ctx, fird_spv_counts_to_lm_comp, {kSB, kSB}, sizeof(ToLmPush),
                      "fird.counts_to_lm"),
      order_pipeline_(ctx, fird_spv_rayset_order_comp, {kSB, kSB, kSB, kSB, kSB},
                      sizeof(gpu::RaysetOrderPush), "fird.rayset.order"),
      bucket_scan_pipeline_(ctx, fird_spv_bucket_scan_comp, {kSB}, 0, "fird.rayset.bucket_scan"),
      walk_start_pipeline_(ctx, fird_spv_walk_start_comp, {kSB, kSB, kSB}, 0, "fird.walk_start"),
      bounce_args_pipeline_(ctx, fird_spv_bounce_args_comp, {kSB, kSB}, sizeof(gpu::BounceArgsPush),
                            "fird.bounce_args"),
      // A pair per pass of one submission: height field, rayset, its ordering, each
      // bounce's trace and ordering, histogram and compare (for each candidate of a batch).
      timer_(ctx, std::uint32_t(kMaxBatchCandidates) * (5 + 2 * (scene.trace.max_bounces + 1))) {
    if (scene.trace.max_bounces > FIRD_MAX_REFLECTIONS)
        throw std::invalid_argument(fmt::format(
            "max_bounces above {} is not supported on the fast path", FIRD_MAX_REFLECTIONS));
    if (scene.trace.rays >= (1ull << 32))
        throw std::invalid_argument(
            "the fast path counts far-field rays in 32 bits: use fewer than 2^32 rays");
    // Constant memory whatever the ray count: batches no larger than one storage
    // buffer binding allows (lavapipe: 128 MiB = 4M rays), and at most 8M rays.
    const auto& limits = ctx.limits();
    // A batch is also no larger than one dispatch covers (maxComputeWorkGroupCount[0]
    // workgroups of the smallest size that walks it: lavapipe's 65535 x 64 < 4M rays).
    const std::uint64_t dispatch_rays =
        std::uint64_t(limits.max_workgroup_count[0]) *
        std::min(FIRD_TRACE_WORKGROUP_SIZE, FIRD_RAYSET_WORKGROUP_SIZE);
    submission_rays_ =
        std::min<std::uint64_t>({limits.max_storage_buffer_range / kRayBytes, 1ull << 23,
                                 dispatch_rays, max_batch_rays ? max_batch_rays : ~0ull,
                                 ctx.max_batch_rays() ? ctx.max_batch_rays() : ~0ull});
    batch_capacity_ = std::min(scene.trace.rays, submission_rays_);
    const std::uint64_t cells_max =
        std::uint64_t(limits.max_workgroup_count[0]) * FIRD_REDUCE_WORKGROUP_SIZE;
    if (std::uint64_t(params_.ff_w) * params_.ff_h > cells_max)
        throw std::invalid_argument(
            fmt::format("farfield {} x {}: more cells than this device's dispatches cover ({})",
                        params_.ff_w, params_.ff_h, cells_max));
    const std::uint64_t ray_bytes = batch_capacity_ * kRayBytes;
    const auto storage = vk::kStorageUsage;
    counters_ = vk::Buffer(ctx, kCountersBytes, storage, vk::MemoryUse::Device, "fird.counters");
    // A slot per candidate of a batch (run_batch): each copies its counters out.
    counters_readback_ = vk::Buffer(ctx, kCountersBytes * kMaxBatchCandidates, storage,
                                    vk::MemoryUse::Readback, "fird.counters.read");
    // The rayset is kept between runs (§5) when it fits the cache budget; otherwise
    // each batch is generated again into a ping-pong buffer (constant memory).
    const std::uint64_t batches = (scene.trace.rays + batch_capacity_ - 1) / batch_capacity_;
    rayset_fits_ = batches * ray_bytes <=
                   std::min<std::uint64_t>(kRaysetCacheBytes, limits.device_local_heap_bytes / 4);
    cache_rayset_ = rayset_fits_;
    rays_ping_ = vk::Buffer(ctx, ray_bytes, storage, vk::MemoryUse::Device, "fird.rays.ping");
    rays_pong_ = vk::Buffer(ctx, ray_bytes, storage, vk::MemoryUse::Device, "fird.rays.pong");
    hits_ = vk::Buffer(ctx, 32, storage, vk::MemoryUse::Device, "fird.hits.unused");
    texel_hits_ = vk::Buffer(ctx, 16, storage, vk::MemoryUse::Device, "fird.texel_hits.unused");
    walk_ = vk::Buffer(ctx, 16, storage, vk::MemoryUse::Device, "fird.walk.unused");
    profile_ = vk::Buffer(ctx, 16, storage, vk::MemoryUse::Device, "fird.profile.unused");
    const QuadtreeLayout q = quadtree_layout(params_.hf_w, params_.hf_h);
    if (q.total_floats > limits.max_texel_buffer_elements)
        throw std::invalid_argument(fmt::format(
            "heightfield {} x {}: its quadtree ({} nodes) exceeds this device's texel buffer "
            "limit ({})",
            params_.hf_w, params_.hf_h, q.total_floats, limits.max_texel_buffer_elements));
    // The height-field passes write the quadtree and the gradients as storage buffers:
    // each must fit one binding (lavapipe: 128 MiB, i.e. 4096 x 4096 texels of gradients).
    const std::uint64_t binding_bytes =
        std::max<std::uint64_t>(q.total_floats * 4, std::uint64_t(params_.hf_w) * params_.hf_h * 8);
    if (binding_bytes > limits.max_storage_buffer_range)
        throw std::invalid_argument(fmt::format(
            "heightfield {} x {}: its buffers ({} MB) exceed this device's storage-buffer range "
            "({} MB); use a smaller height field",
            params_.hf_w, params_.hf_h, binding_bytes >> 20,
            limits.max_storage_buffer_range >> 20));
    current_ = make_reflector_state(ctx, params_, "fird");
    order_buckets_ = vk::Buffer(ctx, gpu::kRaysetOrderBuckets * 4, storage, vk::MemoryUse::Device,
                                "fird.rayset.order_buckets");
    loop_ = vk::Buffer(ctx, gpu::kLoopWords * 4, storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                       vk::MemoryUse::Device, "fird.bounce_loop");
    loop_readback_ = vk::Buffer(ctx, gpu::kLoopWords * 4 * kMaxBatchCandidates, storage,
                                vk::MemoryUse::Readback, "fird.bounce_loop.read");
}

ReflectorState& FastTracer::state() {
    return recording_ == 0 ? current_ : batch_states_[recording_ - 1];
}
const ReflectorState& FastTracer::state() const {
    return recording_ == 0 ? current_ : batch_states_[recording_ - 1];
}

void FastTracer::set_reflector(const ReflectorDesc& reflector) {
    if (current_.reflector && *current_.reflector == reflector) return; // height field current
    if (gpu_family(reflector.family) != spec_[FIRD_SPEC_FAMILY])
        throw std::invalid_argument("the fast path's pipelines were built for another family");
    if (reflector.family == Family::Mesh &&
        (!mesh_ || !current_.reflector || current_.reflector->mesh != reflector.mesh)) {
        // The corner heights are rasterized one texel larger than the height field.
        const std::uint32_t image_max = ctx_->limits().max_image_dimension_2d;
        if (std::max(params_.hf_w, params_.hf_h) + 1 > image_max)
            throw std::invalid_argument(fmt::format(
                "heightfield {} x {}: a mesh reflector is rasterized on {} x {} texel corners, "
                "past this device's largest image ({}); use a smaller height field",
                params_.hf_w, params_.hf_h, params_.hf_w + 1, params_.hf_h + 1, image_max));
        mesh_ = load_mesh(reflector.mesh.resolved_path, reflector.mesh.unit_mm);
        if (!mesh_rasterizer_) mesh_rasterizer_.emplace(*ctx_);
    }
    (void)set_state_reflector(*ctx_, current_, params_, reflector, origin_);
}

void FastTracer::set_rayset_kept(bool kept) {
    cache_rayset_ = kept && rayset_fits_;
    if (!cache_rayset_) rayset_chunks_.clear();
}

void FastTracer::set_seed(std::uint64_t seed) {
    params_ = scene_params(scene_, seed);
    // Every reflector state holds the seed in its parameters: uploaded again, the
    // reflectors (and their height fields) unchanged.
    const auto reseed = [&](ReflectorState& s) {
        s.params = params_;
        if (s.reflector)
            (void)set_reflector_params(s.params, *s.reflector, origin_); // same controls
        s.params_buffer.upload(*ctx_, std::as_bytes(std::span(&s.params, 1)));
    };
    reseed(current_);
    for (ReflectorState& s : batch_states_)
        reseed(s);
    rayset_chunks_.clear(); // the next run generates (and keeps) the new seed's rays
}

void FastTracer::submit(double* untimed_ms, const std::function<void(VkCommandBuffer)>& record) {
    const auto t0 = std::chrono::steady_clock::now();
    timed_.clear();
    ctx_->submit_and_wait([&](VkCommandBuffer cb) {
        timer_.reset(cb);
        record(cb);
    });
    timer_.read();
    for (const TimedPass& p : timed_) {
        const double ms = timer_.elapsed_ms(p.pair);
        *p.stage_ms += ms;
        if (p.bounce_ms) *p.bounce_ms += ms;
    }
    timed_.clear();
    if (!timer_.supported()) *untimed_ms += ms_since(t0);
}

void FastTracer::timed(VkCommandBuffer cb, double* stage_ms, double* bounce_ms,
                       const std::function<void()>& record) {
    const std::uint32_t pair = timer_.begin(cb);
    record();
    timer_.end(cb, pair);
    timed_.push_back({pair, stage_ms, bounce_ms});
}

double FastTracer::rasterize_mesh() {
    if (!state().heightfield_dirty || !mesh_) return 0.0;
    // The paper's z-buffer step for meshes (its own submissions: a render pass).
    const auto t0 = std::chrono::steady_clock::now();
    mesh_rasterizer_->rasterize(*mesh_, origin_, scene_.holder, params_.hf_w, params_.hf_h,
                                state().paper_tree, state().gradients);
    // The texel corners are the centres of a grid one texel larger, half a texel out.
    const double half_x = (scene_.holder.max_mm.x - scene_.holder.min_mm.x) / params_.hf_w / 2;
    const double half_y = (scene_.holder.max_mm.y - scene_.holder.min_mm.y) / params_.hf_h / 2;
    const Holder around{scene_.holder.min_mm - glm::dvec3(half_x, half_y, 0.0),
                        scene_.holder.max_mm + glm::dvec3(half_x, half_y, 0.0)};
    const vk::Buffer corner_gradients(
        *ctx_, std::uint64_t(params_.hf_w + 1) * (params_.hf_h + 1) * 8, vk::kStorageUsage,
        vk::MemoryUse::Device, "fird.mesh_raster.corner_gradients");
    mesh_rasterizer_->rasterize(*mesh_, origin_, around, params_.hf_w + 1, params_.hf_h + 1,
                                state().corners, corner_gradients);
    return ms_since(t0);
}

void FastTracer::record_heightfield(VkCommandBuffer cb, FastRun& run) {
    timed(cb, &run.timings.heightfield_ms, nullptr, [&] {
        constexpr std::uint32_t g = FIRD_HEIGHTFIELD_WORKGROUP_SIZE;
        if (!mesh_) {
            const vk::Binding hf[] = {vk::storage(state().params_buffer),
                                      vk::storage(state().paper_tree),
                                      vk::storage(state().gradients), vk::storage(state().control),
                                      vk::storage(state().corners)};
            heightfield_pipeline_.dispatch(cb, hf, nullptr, groups(params_.hf_w + 1, g),
                                           groups(params_.hf_h + 1, g));
            vk::barrier_all(cb);
        }
        const vk::Binding mm[] = {vk::storage(state().params_buffer),
                                  vk::storage(state().paper_tree),
                                  vk::storage(state().refined_tree), vk::storage(state().corners)};
        for (std::uint32_t level = 0; level < params_.levels; ++level) {
            const gpu::MaxMipPush push{.level = level};
            maxmip_pipeline_.dispatch(cb, mm, &push, groups(params_.level_w[level], g),
                                      groups(params_.level_h[level], g));
            vk::barrier_all(cb);
        }
        const vk::Binding ws[] = {vk::storage(state().params_buffer),
                                  vk::storage(params_.hit_mode == gpu::kHitModePaper
                                                  ? state().paper_tree
                                                  : state().refined_tree),
                                  vk::storage(state().walk_start)};
        walk_start_pipeline_.dispatch(cb, ws, nullptr, 1);
    });
    vk::barrier_all(cb);
}

void FastTracer::build_heightfield(FastRun& run) {
    if (!state().heightfield_dirty) {
        run.heightfield_reused = true;
        return;
    }
    run.timings.heightfield_ms += rasterize_mesh();
    submit(&run.timings.heightfield_ms, [&](VkCommandBuffer cb) { record_heightfield(cb, run); });
    state().heightfield_dirty = false;
}

void FastTracer::record_run_start(VkCommandBuffer cb, bool clear_diagnostics) {
    vkCmdFillBuffer(cb, state().farfield_counts.get(), 0, VK_WHOLE_SIZE, 0);
    if (clear_diagnostics && count_texel_hits_)
        vkCmdFillBuffer(cb, texel_hits_.get(), 0, VK_WHOLE_SIZE, 0);
    if (clear_diagnostics && trace_profile_pipeline_)
        vkCmdFillBuffer(cb, profile_.get(), 0, VK_WHOLE_SIZE, 0);
}

void FastTracer::record_batch_start(VkCommandBuffer cb, std::optional<std::uint64_t> effective,
                                    std::uint64_t emitted) {
    vkCmdFillBuffer(cb, counters_.get(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cb, loop_.get(), 0, VK_WHOLE_SIZE, 0);
    if (effective) {
        vkCmdFillBuffer(cb, counters_.get(), gpu::kCounterEffective * 4, 4,
                        std::uint32_t(*effective));
        vkCmdFillBuffer(cb, counters_.get(), gpu::kCounterDiscarded * 4, 4,
                        std::uint32_t(emitted - *effective));
    }
    vk::barrier_all(cb);
}

void FastTracer::record_rayset(VkCommandBuffer cb, std::uint64_t first, std::uint64_t n,
                               const vk::Buffer& rays, FastRun& run) {
    if (!rayset_ordered_at_birth()) {
        vkCmdFillBuffer(cb, order_buckets_.get(), 0, VK_WHOLE_SIZE, 0);
        vk::barrier_all(cb);
    }
    timed(cb, &run.timings.rayset_ms, nullptr, [&] {
        const vk::Binding b[] = {vk::storage(state().params_buffer), vk::storage(rays),
                                 vk::storage(counters_), vk::storage(order_buckets_)};
        const gpu::RaysetPush push{.first_lo = std::uint32_t(first),
                                   .first_hi = std::uint32_t(first >> 32),
                                   .count = std::uint32_t(n),
                                   .keep_all = skips_.discard_before_trace ? 0u : 1u};
        rayset_pipeline_.dispatch(cb, b, &push, groups(n, FIRD_RAYSET_WORKGROUP_SIZE));
    });
    vk::barrier_all(cb);
}

void FastTracer::record_bounce_args(VkCommandBuffer cb, std::uint32_t stage, std::uint32_t bounce) {
    const vk::Binding b[] = {vk::storage(counters_), vk::storage(loop_)};
    const gpu::BounceArgsPush push{.stage = stage,
                                   .bounce = bounce,
                                   .trace_empty = skips_.skip_empty_bounces ? 0u : 1u,
                                   .groups_max = ctx_->limits().max_workgroup_count[0]};
    bounce_args_pipeline_.dispatch(cb, b, &push, 1);
    vk::barrier_all(cb);
}

void FastTracer::record_order(VkCommandBuffer cb, const vk::Buffer& from, const vk::Buffer& to,
                              bool reflected) {
    const vk::Binding scan[] = {vk::storage(order_buckets_)};
    bucket_scan_pipeline_.dispatch_indirect(cb, scan, nullptr, loop_, gpu::kLoopScanArgs * 4);
    vk::barrier_all(cb);
    const vk::Binding b[] = {vk::storage(state().params_buffer), vk::storage(from), vk::storage(to),
                             vk::storage(order_buckets_), vk::storage(loop_)};
    const gpu::RaysetOrderPush push{.reflected = reflected ? 1u : 0u};
    order_pipeline_.dispatch_indirect(cb, b, &push, loop_, gpu::kLoopOrderArgs * 4);
    vk::barrier_all(cb);
}

void FastTracer::record_rayset_order(VkCommandBuffer cb, const vk::Buffer& from,
                                     const vk::Buffer& to, FastRun& run) {
    timed(cb, &run.timings.rayset_ms, nullptr, [&] {
        record_bounce_args(cb, gpu::kArgsOrderRayset, 0);
        record_order(cb, from, to, false);
    });
}

void FastTracer::dispatch_trace(VkCommandBuffer cb, const vk::Buffer& in, const vk::Buffer& out,
                                const vk::Buffer& counters, const vk::Buffer& farfield,
                                const gpu::TracePush& push, bool record_walk,
                                std::optional<std::uint32_t> groups) {
    const vk::Binding b[] = {
        vk::storage(state().params_buffer),
        vk::storage(in),
        vk::storage(out),
        vk::storage(counters),
        vk::texel(params_.hit_mode == gpu::kHitModePaper ? state().paper_view
                                                         : state().refined_view),
        vk::texel(params_.hit_mode == gpu::kHitModePaper ? state().paper_view
                                                         : state().corners_view),
        vk::texel(state().gradients_view),
        vk::storage(farfield),
        vk::storage(hits_),
        vk::storage(order_buckets_),
        vk::storage(texel_hits_),
        vk::storage(walk_),
        vk::storage(profile_),
        vk::storage(state().walk_start),
        vk::storage(state().control),
        vk::storage(loop_)};
    // The variant that does what the push constants ask and no more (the walk-recording
    // one also records hits; profile counts come from plain runs only).
    const bool diagnostics = push.record_hits != 0u || push.count_texel_hits != 0u;
    if (diagnostics && !record_walk && !trace_diagnostics_pipeline_) {
        trace_diagnostics_pipeline_.emplace(
            trace_pipeline(*ctx_, spec_, {FIRD_SPEC_DIAGNOSTICS}, "fird.trace.diagnostics"));
    }
    const vk::ComputePipeline& p = record_walk               ? *trace_walk_pipeline_
                                   : diagnostics             ? *trace_diagnostics_pipeline_
                                   : trace_profile_pipeline_ ? *trace_profile_pipeline_
                                                             : trace_pipeline_;
    if (groups)
        p.dispatch(cb, b, &push, *groups);
    else
        p.dispatch_indirect(cb, b, &push, loop_, gpu::kLoopTraceArgs * 4);
}

void FastTracer::record_bounces(VkCommandBuffer cb, const vk::Buffer& rays, FastRun& run,
                                bool record_hits) {
    // Every bounce is recorded, each sized on the device by the one before (bounce_args.comp):
    // a bounce without active rays is an indirect dispatch of 0 groups, which costs next
    // to nothing (the skip of empty bounces; with the skip off it runs one workgroup).
    // Bounded by the scene's bounces, like the loop on the device it replaces.
    record_bounce_args(cb, gpu::kArgsFirstBounce, 0);
    const vk::Buffer* in = &rays;
    const vk::Buffer* out = &rays_ping_;
    const std::uint32_t n = passes();
    for (std::uint32_t bounce = 0; bounce < n; ++bounce) {
        // The rays reflected here are ordered by direction for the next bounce, as the
        // rayset is, unless there are too few for the ordering to pay (kOrderMinRays,
        // decided on the device: they are then copied as they are).
        const bool order = bounce + 1 < n;
        BounceProfile& profile = run.bounces[bounce];
        timed(cb, &run.timings.trace_ms, &profile.trace_ms, [&] {
            if (order) {
                vkCmdFillBuffer(cb, order_buckets_.get(), 0, VK_WHOLE_SIZE, 0);
                vk::barrier_all(cb);
            }
            const gpu::TracePush push{.bounce = bounce,
                                      .final_check = bounce == params_.max_bounces ? 1u : 0u,
                                      .record_hits = record_hits && bounce == 0 ? 1u : 0u,
                                      .order_output = order ? 1u : 0u,
                                      .count_texel_hits = count_texel_hits_ ? 1u : 0u,
                                      .walk_to_box_top = skips_.end_walk_at_reflector_top ? 0u : 1u,
                                      .walk_from_root = skips_.start_walk_below_source ? 0u : 1u};
            dispatch_trace(cb, *in, *out, counters_, state().farfield_counts, push, false,
                           std::nullopt);
            vk::barrier_all(cb);
        });
        if (!order) break;
        // Into the other ping-pong buffer (this bounce's input is consumed).
        const vk::Buffer* spare = (out == &rays_ping_) ? &rays_pong_ : &rays_ping_;
        timed(cb, &run.timings.trace_ms, &profile.order_ms, [&] {
            record_bounce_args(cb, gpu::kArgsNextBounce, bounce + 1);
            record_order(cb, *out, *spare, true);
        });
        in = spare;
        out = (in == &rays_ping_) ? &rays_pong_ : &rays_ping_;
        // A window sharing the device draws between bounces (the bounce loop is sized on
        // the device, so the pieces need nothing from the host).
        ctx_->yield_queue(cb);
    }
}

void FastTracer::record_to_lm(VkCommandBuffer cb, FastRun& run) {
    const std::uint32_t cells = farfield_cells();
    timed(cb, &run.timings.histogram_ms, nullptr, [&] {
        const vk::Binding b[] = {vk::storage(state().farfield_counts),
                                 vk::storage(state().farfield_lm)};
        const ToLmPush push{cells, float(run.energy_per_ray_lm)};
        to_lm_pipeline_.dispatch(cb, b, &push, groups(cells, FIRD_REDUCE_WORKGROUP_SIZE));
    });
    vk::barrier_all(cb);
}

void FastTracer::record_batch_end(VkCommandBuffer cb, std::size_t slot) {
    const VkBufferCopy loop{.dstOffset = slot * gpu::kLoopWords * 4, .size = gpu::kLoopWords * 4};
    vkCmdCopyBuffer(cb, loop_.get(), loop_readback_.get(), 1, &loop);
    const VkBufferCopy counters{.dstOffset = slot * kCountersBytes, .size = kCountersBytes};
    vkCmdCopyBuffer(cb, counters_.get(), counters_readback_.get(), 1, &counters);
    vk::barrier_to_host(cb);
}

void FastTracer::tally_batch(FastRun& run, std::size_t slot) const {
    // Tally this batch's counters (32-bit on the device, summed over the copies in 64 bits).
    const auto* counters = static_cast<const std::uint32_t*>(counters_readback_.data()) +
                           slot * gpu::kTallyCopies * gpu::kCounterCount;
    const auto total = [&](std::uint32_t counter) {
        std::uint64_t sum = 0;
        for (std::uint32_t c = 0; c < gpu::kTallyCopies; ++c)
            sum += counters[c * gpu::kCounterCount + counter];
        return sum;
    };
    RayTally& t = run.tally;
    t.discarded += total(gpu::kCounterDiscarded);
    t.direct += total(gpu::kCounterDirect);
    t.farfield += total(gpu::kCounterFarField);
    t.lost += total(gpu::kCounterLost);
    t.below_surface += total(gpu::kCounterBelow);
    run.aborted += total(gpu::kCounterAborted);
    for (std::uint32_t r = 0; r <= params_.max_bounces; ++r)
        t.by_reflections[r] += total(gpu::kCounterByReflections + r);
    const auto* loop =
        static_cast<const std::uint32_t*>(loop_readback_.data()) + slot * gpu::kLoopWords;
    for (std::size_t b = 0; b < run.bounces.size(); ++b)
        run.bounces[b].rays += loop[gpu::kLoopBounceRays + b];
}

void FastTracer::finish(FastRun& run) const {
    // Bounces after the last with rays traced nothing (where empty ones are skipped, they
    // were dispatched with 0 groups): listed only when the skip is off, as before.
    std::size_t traced = run.bounces.size();
    if (skips_.skip_empty_bounces)
        while (traced > 0 && run.bounces[traced - 1].rays == 0)
            --traced;
    run.bounces.resize(traced);
    const RayTally& t = run.tally;
    if (t.emitted != t.discarded + t.direct + t.farfield + t.lost)
        throw std::logic_error(
            fmt::format("fast path energy balance broken: {} emitted, {} accounted", t.emitted,
                        t.discarded + t.direct + t.farfield + t.lost));
}

FastRun FastTracer::new_run(std::uint64_t emitted) const {
    FastRun run;
    run.tally.emitted = emitted;
    run.tally.by_reflections.assign(params_.max_bounces + 1, 0);
    run.bounces.assign(passes(), {});
    run.energy_per_ray_lm = scene_.source.flux_lm / double(std::max<std::uint64_t>(emitted, 1));
    return run;
}

FastRun FastTracer::run(const std::function<void(VkCommandBuffer)>& then) {
    if (!current_.reflector) throw std::logic_error("FastTracer::run: no reflector set");
    const auto t0 = std::chrono::steady_clock::now();
    FastRun run = new_run(scene_.trace.rays);
    if (!skips_.keep_rayset) rayset_chunks_.clear();
    if (!skips_.keep_heightfield) state().heightfield_dirty = true;
    run.heightfield_reused = !state().heightfield_dirty;
    run.timings.heightfield_ms += rasterize_mesh();
    bool first_submission = true;
    // The height field (when it changed) and the clears go into the first submission.
    const auto record_start = [&](VkCommandBuffer cb) {
        if (!first_submission) return;
        if (state().heightfield_dirty) record_heightfield(cb, run);
        record_run_start(cb, true);
    };
    const auto submitted = [&] {
        first_submission = false;
        state().heightfield_dirty = false;
    };
    const std::uint64_t batches = (scene_.trace.rays + batch_capacity_ - 1) / batch_capacity_;
    for (std::size_t batch = 0; batch < batches; ++batch) {
        const std::uint64_t first = batch * batch_capacity_;
        const std::uint64_t n = std::min(batch_capacity_, scene_.trace.rays - first);
        const bool last = batch + 1 == batches;
        // The rayset does not depend on the reflector (§5): a kept batch is reused.
        const bool reuse = batch < rayset_chunks_.size();
        const bool sort = !reuse && !rayset_ordered_at_birth();
        // Kept for the next run (a buffer per batch), or generated again each run into the
        // ping-pong buffer the first bounce does not write (its input is consumed by then).
        const auto keep = [&](std::uint64_t ray_count) -> const vk::Buffer* {
            if (!cache_rayset_) return &rays_pong_;
            rayset_chunks_.push_back(
                {vk::Buffer(*ctx_, std::max<std::uint64_t>(ray_count, 1) * kRayBytes,
                            vk::kStorageUsage, vk::MemoryUse::Device,
                            fmt::format("fird.rayset.{}", batch)),
                 0});
            return &rayset_chunks_.back().rays;
        };
        const vk::Buffer* rays = nullptr;
        bool generated = false; // the rayset pass ran in a submission of its own
        if (reuse) {
            run.rayset_reused = true;
            rays = &rayset_chunks_[batch].rays;
        } else if (!sort) {
            rays = keep(n); // emitted in direction order: generated in place
        } else if (cache_rayset_) {
            // A kept sorted batch takes the memory of its effective rays alone, a count the
            // host learns from the rayset pass: it is generated in a submission of its own
            // (the first run of a rayset only; later runs reuse it).
            submit(&run.timings.rayset_ms, [&](VkCommandBuffer cb) {
                record_start(cb);
                record_batch_start(cb, std::nullopt, n);
                record_rayset(cb, first, n, rays_ping_, run);
                record_batch_end(cb);
            });
            submitted();
            generated = true;
            rays = keep(static_cast<const std::uint32_t*>(
                counters_readback_.data())[gpu::kCounterEffective]);
        } else {
            rays = &rays_pong_; // sorted into it from the ping-pong buffer
        }
        submit(&run.timings.trace_ms, [&](VkCommandBuffer cb) {
            record_start(cb);
            if (!generated)
                record_batch_start(
                    cb, reuse ? std::optional(rayset_chunks_[batch].effective) : std::nullopt, n);
            if (!reuse && !generated) record_rayset(cb, first, n, sort ? rays_ping_ : *rays, run);
            if (sort) record_rayset_order(cb, rays_ping_, *rays, run);
            ctx_->yield_queue(cb);
            record_bounces(cb, *rays, run, false);
            if (last) {
                record_to_lm(cb, run);
                if (then) {
                    timed(cb, &run.timings.compare_ms, nullptr, [&] { then(cb); });
                    vk::barrier_all(cb);
                }
            }
            record_batch_end(cb);
        });
        submitted();
        if (cache_rayset_ && !reuse)
            rayset_chunks_.back().effective = static_cast<const std::uint32_t*>(
                counters_readback_.data())[gpu::kCounterEffective];
        tally_batch(run);
    }
    finish(run);
    if (trace_profile_pipeline_) read_profile(run);
    run.timings.total_ms = ms_since(t0);
    return run;
}

std::vector<FastRun> FastTracer::run_batch(std::span<const ReflectorDesc> reflectors,
                                           const BatchCompare& then) {
    std::vector<FastRun> runs;
    runs.reserve(reflectors.size());
    // One at a time: run() with the candidate's compare.
    const auto single = [&](std::size_t k) {
        set_reflector(reflectors[k]);
        std::function<void(VkCommandBuffer)> compare;
        if (then) compare = [&](VkCommandBuffer cb) { then(cb, k, current_.farfield_lm); };
        runs.push_back(run(compare));
    };
    // One submission holds every candidate's passes when the rays are one kept batch that
    // each candidate reads (and nothing accumulates over candidates: diagnostics, profile).
    const bool one_batch_of_rays = scene_.trace.rays <= batch_capacity_;
    const bool batchable = one_batch_of_rays && cache_rayset_ && skips_.keep_rayset && !mesh_ &&
                           !count_texel_hits_ && !trace_profile_pipeline_;
    std::size_t k = 0;
    if (!batchable || rayset_chunks_.empty()) {
        // The first run generates the rayset that the others reuse.
        for (; k < reflectors.size() && (!batchable || rayset_chunks_.empty()); ++k)
            single(k);
    }
    // No more ray-candidates in one submission than one batch of rays may hold: a
    // submission as long as one batch's (a driver's timeout, a window's frame or an
    // interruption waits for no more).
    const std::size_t per_submission = std::size_t(std::clamp<std::uint64_t>(
        submission_rays_ / std::max<std::uint64_t>(scene_.trace.rays, 1), 1, kMaxBatchCandidates));
    while (k < reflectors.size()) {
        std::size_t m = std::min(per_submission, reflectors.size() - k);
        // Height fields for the others as memory allows (the budget, or the device's).
        while (batch_states_.size() < m - 1) {
            try {
                batch_states_.push_back(make_reflector_state(
                    *ctx_, params_, fmt::format("fird.candidate{}", batch_states_.size() + 1)));
            } catch (const vk::VulkanError& e) {
                if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY &&
                    e.result() != VK_ERROR_OUT_OF_HOST_MEMORY)
                    throw;
                m = batch_states_.size() + 1;
            }
        }
        if (m == 1) {
            single(k++);
            continue;
        }
        for (std::size_t j = 0; j + 1 < m; ++j)
            (void)set_state_reflector(*ctx_, batch_states_[j], params_, reflectors[k + j], origin_);
        set_reflector(reflectors[k + m - 1]);
        for (std::size_t j = 0; j < m; ++j)
            runs.push_back(new_run(scene_.trace.rays));
        run_batch_submission(std::span(runs).subspan(k, m), then, k);
        k += m;
    }
    return runs;
}

void FastTracer::run_batch_submission(std::span<FastRun> runs, const BatchCompare& then,
                                      std::size_t first) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t m = runs.size();
    // Candidate j's state: batch_states_[j], the last one current_.
    const auto slot = [&](std::size_t j) { return j + 1 < m ? j + 1 : std::size_t(0); };
    for (std::size_t j = 0; j < m; ++j) {
        recording_ = slot(j);
        if (!skips_.keep_heightfield) state().heightfield_dirty = true;
        runs[j].heightfield_reused = !state().heightfield_dirty;
        runs[j].rayset_reused = true;
    }
    struct Restore {
        std::size_t& recording;
        ~Restore() { recording = 0; }
    } restore{recording_};
    double untimed_ms = 0.0;
    const RaysetChunk& rays = rayset_chunks_.front();
    submit(&untimed_ms, [&](VkCommandBuffer cb) {
        for (std::size_t j = 0; j < m; ++j) {
            recording_ = slot(j);
            FastRun& run = runs[j];
            if (state().heightfield_dirty) record_heightfield(cb, run);
            record_run_start(cb, false);
            record_batch_start(cb, rays.effective, scene_.trace.rays);
            record_bounces(cb, rays.rays, run, false);
            record_to_lm(cb, run);
            if (then) {
                timed(cb, &run.timings.compare_ms, nullptr,
                      [&] { then(cb, first + j, state().farfield_lm); });
                vk::barrier_all(cb);
            }
            record_batch_end(cb, j);
        }
    });
    const double share_ms = ms_since(t0) / double(m);
    for (std::size_t j = 0; j < m; ++j) {
        recording_ = slot(j);
        state().heightfield_dirty = false;
        tally_batch(runs[j], j);
        finish(runs[j]);
        runs[j].timings.trace_ms += untimed_ms / double(m);
        runs[j].timings.total_ms = share_ms; // its share of the submission's wall time
    }
}

FastRun FastTracer::run_rays(const std::vector<Ray>& rays, std::vector<glm::dvec4>* hits) {
    if (!current_.reflector) throw std::logic_error("FastTracer::run_rays: no reflector set");
    if (rays.size() > batch_capacity_)
        throw std::invalid_argument("run_rays: more rays than one batch holds");
    FastRun run = new_run(rays.size());
    run.heightfield_reused = !state().heightfield_dirty;
    run.timings.heightfield_ms += rasterize_mesh();
    // Upload all rays (the caller chose them; none are discarded here), in the frame.
    std::vector<float> packed(rays.size() * 8, 0.0f);
    for (std::size_t i = 0; i < rays.size(); ++i)
        for (int k = 0; k < 3; ++k) {
            packed[i * 8 + k] = float(rays[i].origin[k] - origin_[k]);
            packed[i * 8 + 4 + k] = float(rays[i].direction[k]);
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
        record_bounces(cb, uploaded, run, hits != nullptr);
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

void FastTracer::set_skips(const FastPathSkips& skips) {
    if (skips.discard_before_trace != skips_.discard_before_trace) rayset_chunks_.clear();
    skips_ = skips;
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

std::vector<float> FastTracer::read_quadtree() {
    FastRun unused;
    build_heightfield(unused);
    const QuadtreeLayout q = quadtree_layout(params_.hf_w, params_.hf_h);
    std::vector<float> tree = state().paper_tree.download_as<float>(*ctx_, q.total_floats);
    for (float& h : tree)
        h = float(double(h) + origin_.z); // out of the frame
    return tree;
}

std::vector<glm::vec2> FastTracer::read_gradients() {
    FastRun unused;
    build_heightfield(unused);
    return state().gradients.download_as<glm::vec2>(*ctx_,
                                                    std::size_t(params_.hf_w) * params_.hf_h);
}

std::vector<RayPath> FastTracer::trace_paths(const std::vector<Ray>& rays, std::size_t pick,
                                             std::vector<WalkStep>* walk) {
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
    vk::Buffer farfield(*ctx_, std::uint64_t(farfield_cells()) * 4, vk::kStorageUsage,
                        vk::MemoryUse::Device, "fird.paths.farfield");
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
    // starts at its hit, skipping the texel it left (the w components carry it).
    for (std::uint32_t bounce = 0; bounce < params_.max_bounces && !live.empty(); ++bounce) {
        std::vector<float> packed(live.size() * 8, 0.0f);
        for (std::size_t k = 0; k < live.size(); ++k) {
            const Live& l = live[k];
            for (int c = 0; c < 3; ++c) {
                packed[k * 8 + c] = l.origin[c];
                packed[k * 8 + 4 + c] = l.direction[c];
            }
            if (bounce > 0) {
                const std::int32_t tx = std::int32_t(l.texel % params_.hf_w);
                const std::int32_t ty = std::int32_t(l.texel / params_.hf_w);
                std::memcpy(&packed[k * 8 + 3], &tx, 4);
                std::memcpy(&packed[k * 8 + 7], &ty, 4);
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
            const gpu::TracePush push{.bounce = bounce, .record_hits = 1u, .walk_ray = walk_ray};
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

std::vector<Ray> FastTracer::rayset() const {
    if (rayset_chunks_.size() * batch_capacity_ < scene_.trace.rays)
        throw std::logic_error("FastTracer::rayset: no rayset kept");
    std::vector<Ray> rays;
    for (const RaysetChunk& chunk : rayset_chunks_) {
        const auto packed = chunk.rays.download_as<float>(*ctx_, chunk.effective * 8);
        for (std::size_t i = 0; i < chunk.effective; ++i) {
            const float* r = &packed[i * 8];
            rays.push_back(Ray{glm::dvec3(r[0], r[1], r[2]) + origin_, {r[4], r[5], r[6]}});
        }
    }
    return rays;
}

std::vector<double> FastTracer::read_farfield() const {
    const auto f = state().farfield_lm.download_as<float>(*ctx_, farfield_cells());
    return {f.begin(), f.end()};
}

double device_l2(const vk::Context& ctx, const ReducePass& reduce, const vk::Buffer& a,
                 const vk::Buffer& b, std::uint32_t cells, double* compare_ms) {
    const auto t0 = std::chrono::steady_clock::now();
    const double sum = reduce.sum_squared_difference(ctx, a, b, cells);
    if (compare_ms) *compare_ms = ms_since(t0);
    return std::sqrt(std::max(0.0, sum));
}

} // namespace fird
