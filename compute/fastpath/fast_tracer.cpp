// The fast tracer's setup and one evaluation: buffers and pipelines for the scene, the
// current reflector and seed, and run(), whose passes (the other fast_tracer_*.cpp files)
// are recorded into one submission per batch of rays.
#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <stdexcept>

#include <fmt/format.h>

#include <glm/geometric.hpp>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

#include "bounce_args_comp.h"
#include "bucket_scan_comp.h"
#include "counts_to_lm_comp.h"
#include "heightfield_comp.h"
#include "maxmip_comp.h"
#include "rayset_comp.h"
#include "rayset_order_comp.h"
#include "walk_start_comp.h"

namespace fird {

using namespace fast_tracer_detail;

namespace {
using HeightfieldSpec = std::array<std::uint32_t, FIRD_SPEC_REFINED_ONLY + 1>;
// heightfield.comp's constants: the scene's and FIRD_SPEC_REFINED_ONLY.
HeightfieldSpec heightfield_specialization(const std::array<std::uint32_t, FIRD_SPEC_COUNT>& scene,
                                           bool refined_only) {
    HeightfieldSpec spec{};
    std::copy(scene.begin(), scene.end(), spec.begin());
    spec[FIRD_SPEC_REFINED_ONLY] = refined_only ? 1u : 0u;
    return spec;
}
// maxmip.comp's: the scene's (unused there), FIRD_SPEC_MAXMIP_LEVEL_ZERO and
// FIRD_SPEC_REFINED_ONLY.
HeightfieldSpec maxmip_specialization(bool level_zero, bool refined_only) {
    HeightfieldSpec spec{};
    spec[FIRD_SPEC_MAXMIP_LEVEL_ZERO] = level_zero ? 1u : 0u;
    spec[FIRD_SPEC_REFINED_ONLY] = refined_only ? 1u : 0u;
    return spec;
}
// The plain run's two trace pipelines (FIRD_SPEC_BOUNCE_KIND: the source's rays, reflected
// rays), created on two threads: the largest shader FIRD has, each ~40 ms to create on
// lavapipe even from its shader cache (a whole evaluation's start-up).
std::array<passes::TracePass, 2>
plain_trace_pipelines(const vk::Context& ctx,
                      const std::array<std::uint32_t, FIRD_SPEC_COUNT>& spec) {
    auto reflected = std::async(std::launch::async, [&] {
        return trace_pipeline(ctx, spec, {}, "fird.trace.reflected", gpu::kBounceReflected);
    });
    passes::TracePass source =
        trace_pipeline(ctx, spec, {}, "fird.trace.source", gpu::kBounceFromSource);
    return {std::move(source), reflected.get()};
}
} // namespace

FastTracer::FastTracer(const vk::Context& ctx, const Scene& scene, std::uint64_t seed,
                       std::uint64_t max_batch_rays)
    : ctx_(&ctx), scene_(scene), origin_(fird::frame_origin(scene.holder)),
      params_(scene_params(scene, seed)), spec_(specialization(params_, scene.reflector.family)),
      rayset_pipeline_(ctx, fird_spv_rayset_comp, "fird.rayset", spec_),
      heightfield_pipeline_(ctx, fird_spv_heightfield_comp, "fird.heightfield",
                            heightfield_specialization(spec_, false)),
      heightfield_refined_pipeline_(ctx, fird_spv_heightfield_comp, "fird.heightfield.refined",
                                    heightfield_specialization(spec_, true)),
      maxmip_level0_pipeline_(ctx, fird_spv_maxmip_comp, "fird.maxmip.level0",
                              maxmip_specialization(true, false)),
      maxmip_pipeline_(ctx, fird_spv_maxmip_comp, "fird.maxmip",
                       maxmip_specialization(false, false)),
      maxmip_refined_pipeline_(ctx, fird_spv_maxmip_comp, "fird.maxmip.refined",
                               maxmip_specialization(false, true)),
      trace_pipelines_(plain_trace_pipelines(ctx, spec_)),
      to_lm_pipeline_(ctx, fird_spv_counts_to_lm_comp, "fird.counts_to_lm"),
      order_pipeline_(ctx, fird_spv_rayset_order_comp, "fird.rayset.order"),
      bucket_scan_pipeline_(ctx, fird_spv_bucket_scan_comp, "fird.rayset.bucket_scan"),
      walk_start_pipeline_(ctx, fird_spv_walk_start_comp, "fird.walk_start"),
      bounce_args_pipeline_(ctx, fird_spv_bounce_args_comp, "fird.bounce_args"),
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
    // buffer binding allows (lavapipe: 128 MiB = 4M rays; the rays themselves are read
    // through texel views now, whose limit is below, but the batch sizes every
    // measurement in docs/benchmarks.md used are kept), and at most 8M rays, or 32M
    // (two ray tables of 1 GiB) on a discrete GPU with 16 GiB or more of its own memory,
    // where the paper's 1e7 rays are then one submission (an H200 traces them in ~1-9 ms,
    // 32M in ~25 ms: far from any driver's timeout). An integrated GPU's "own" memory is
    // the system's: it keeps 8M.
    const auto& limits = ctx.limits();
    const bool big_discrete =
        ctx.summary().type == "discrete" && limits.device_local_heap_bytes >= (16ull << 30);
    const std::uint64_t most_rays = big_discrete ? 1ull << 25 : 1ull << 23;
    // A batch is also no larger than one dispatch covers (maxComputeWorkGroupCount[0]
    // workgroups of the smallest size that walks it: lavapipe's 65535 x 64 < 4M rays).
    const std::uint64_t dispatch_rays =
        std::uint64_t(limits.max_workgroup_count[0]) *
        std::min(FIRD_TRACE_WORKGROUP_SIZE, FIRD_RAYSET_WORKGROUP_SIZE);
    // A batch's rays are read as texels (ray_table.hpp): no more than one view holds.
    submission_rays_ =
        std::min<std::uint64_t>({limits.max_storage_buffer_range / kRayBytes,
                                 limits.max_texel_buffer_elements / gpu::kRayTexels, most_rays,
                                 dispatch_rays, max_batch_rays ? max_batch_rays : ~0ull,
                                 ctx.max_batch_rays() ? ctx.max_batch_rays() : ~0ull});
    // A ray file's batch is read on the host into a buffer of its own: batches of at most
    // kRayFileBatchRays keep those buffers (two of 24 MiB) and the host's share bounded.
    if (scene.source.kind == SourceKind::RayFile)
        submission_rays_ = std::min(submission_rays_, kRayFileBatchRays);
    batch_capacity_ = std::min(scene.trace.rays, submission_rays_);
    const std::uint64_t cells_max =
        std::uint64_t(limits.max_workgroup_count[0]) * FIRD_REDUCE_WORKGROUP_SIZE;
    if (std::uint64_t(params_.ff_w) * params_.ff_h > cells_max)
        throw std::invalid_argument(
            fmt::format("farfield {} x {}: more cells than this device's dispatches cover ({})",
                        params_.ff_w, params_.ff_h, cells_max));
    // A reflectance below 1 counts the far field per reflection order (counts_to_lm.comp).
    const std::uint64_t counts_bytes =
        std::uint64_t(params_.ff_w) * params_.ff_h * 4 * params_.farfield_layers;
    if (counts_bytes > limits.max_storage_buffer_range)
        throw std::invalid_argument(fmt::format(
            "farfield {} x {} counted per reflection order ([reflector.material] reflectance "
            "below 1, {} layers: [trace] max_bounces + 1) needs {} MB, past this device's "
            "storage-buffer range ({} MB); use fewer bounces or a coarser far field",
            params_.ff_w, params_.ff_h, params_.farfield_layers, counts_bytes >> 20,
            limits.max_storage_buffer_range >> 20));
    // counts_to_lm.comp reads the counts, and the compare the lumens, through texel views.
    vk::require_texel_count(
        ctx, std::uint64_t(params_.ff_w) * params_.ff_h * params_.farfield_layers,
        fmt::format("farfield {} x {} ({} layers: one per reflection order where the "
                    "reflectance is below 1); use a coarser far field",
                    params_.ff_w, params_.ff_h, params_.farfield_layers));
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
    rays_ping_ = make_ray_table(ctx, batch_capacity_, vk::MemoryUse::Device, "fird.rays.ping");
    rays_pong_ = make_ray_table(ctx, batch_capacity_, vk::MemoryUse::Device, "fird.rays.pong");
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
    // A photometric source's distribution (emitter.h); one unused float for the others. A
    // ray file's batches of rays, written by the host before their rayset pass.
    const std::vector<float> no_table(1, 0.0f);
    const std::vector<float>& table =
        scene.source.table.floats ? *scene.source.table.floats : no_table;
    emitter_table_ =
        make_float_table(ctx, table.size(), vk::MemoryUse::Device, "fird.rayset.emitter_table");
    emitter_table_.values.upload(ctx, std::span<const float>(table));
    if (scene.source.kind == SourceKind::RayFile)
        for (int k = 0; k < 2; ++k)
            ray_file_tables_[k] =
                make_float_table(ctx, batch_capacity_ * gpu::kRayFileFloats, vk::MemoryUse::Upload,
                                 fmt::format("fird.rayset.ray_file.{}", k));
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

void FastTracer::require_family(const ReflectorDesc& reflector) const {
    if (gpu_family(reflector.family) != spec_[FIRD_SPEC_FAMILY])
        throw std::invalid_argument("the fast path's pipelines were built for another family");
}

void FastTracer::set_reflector(const ReflectorDesc& reflector) {
    if (current_.reflector && *current_.reflector == reflector) return; // height field current
    require_family(reflector);
    if (reflector.material != scene_.reflector.material)
        throw std::invalid_argument(
            "the fast path's far-field layers and finish were set for another material");
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

void FastTracer::set_source(const SourceDesc& source) {
    if (source.kind != scene_.source.kind || !(source.table == scene_.source.table))
        throw std::invalid_argument("FastTracer::set_source: another kind of source needs "
                                    "another tracer");
    scene_.source = source;
    set_seed(std::uint64_t(params_.seed_lo) | (std::uint64_t(params_.seed_hi) << 32));
    // The walk's start level (walk_start.comp) depends on the source's box: made again
    // with the height field's passes.
    current_.heightfield_dirty = true;
    for (ReflectorState& s : batch_states_)
        s.heightfield_dirty = true;
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

void FastTracer::set_skips(const FastPathSkips& skips) {
    if (skips.discard_before_trace != skips_.discard_before_trace) rayset_chunks_.clear();
    skips_ = skips;
}

FastRun FastTracer::new_run(std::uint64_t emitted) const {
    FastRun run;
    run.tally.emitted = emitted;
    run.tally.by_reflections.assign(params_.max_bounces + 1, 0);
    run.tally.lost_by_reflections.assign(params_.max_bounces + 1, 0);
    run.tally.reflectance = scene_.reflector.material.reflectance;
    run.tally.direct_binned = params_.bin_direct != 0u;
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
    const std::size_t kept_batches = rayset_chunks_.size();
    // A ray file's batches are read on the host: each batch's read (after the first) runs on
    // a thread while the device traces the batch before it, into the other table. The host
    // time waited for a read counts in the rayset pass's time.
    const bool read_rays = scene_.source.kind == SourceKind::RayFile;
    const auto batch_rays = [&](std::size_t batch) {
        return std::min(batch_capacity_, scene_.trace.rays - batch * batch_capacity_);
    };
    std::future<void> next_read;
    for (std::size_t batch = 0; batch < batches; ++batch) {
        const std::uint64_t first = batch * batch_capacity_;
        const std::uint64_t n = batch_rays(batch);
        const bool last = batch + 1 == batches;
        // The rayset does not depend on the reflector (§5): a kept batch is reused.
        const bool reuse = batch < kept_batches;
        const bool sort = !reuse && !rayset_ordered_at_birth();
        // Kept for the next run (a buffer per batch), or generated again each run into the
        // ping-pong buffer the first bounce does not write (its input is consumed by then).
        const auto keep = [&](std::uint64_t ray_count) -> const RayTable* {
            if (!cache_rayset_) return &rays_pong_;
            rayset_chunks_.push_back({make_ray_table(*ctx_, ray_count, vk::MemoryUse::Device,
                                                     fmt::format("fird.rayset.{}", batch)),
                                      0});
            return &rayset_chunks_.back().rays;
        };
        const RayTable* rays = nullptr;
        bool generated = false; // the rayset pass ran in a submission of its own
        if (read_rays && !reuse) {
            const auto t_read = std::chrono::steady_clock::now();
            if (next_read.valid())
                next_read.get(); // rethrows a failed read
            else
                read_ray_file_batch(first, n);
            run.timings.rayset_ms += ms_since(t_read);
            if (batch + 1 < batches)
                next_read = std::async(std::launch::async, [this, next = batch + 1, &batch_rays] {
                    read_ray_file_batch(next * batch_capacity_, batch_rays(next));
                });
        }
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
            record_bounces(cb, *rays, first, run);
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

std::vector<double> FastTracer::read_farfield() const {
    const auto f = state().farfield_lm.values.download_as<float>(*ctx_, farfield_cells());
    return {f.begin(), f.end()};
}

double device_l2(const vk::Context& ctx, const ReducePass& reduce, const FloatTable& a,
                 const FloatTable& b, std::uint32_t cells, double* compare_ms,
                 ReduceDifference difference) {
    const auto t0 = std::chrono::steady_clock::now();
    const double sum = reduce.sum_squared_difference(ctx, a, b, cells, difference);
    if (compare_ms) *compare_ms = ms_since(t0);
    return std::sqrt(std::max(0.0, sum));
}

} // namespace fird
