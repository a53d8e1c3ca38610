// The bounce tracer: the RQRM trace pass and the loop over bounces, each sized on the
// device by the one before.
#include "fast_tracer.hpp"

#include <chrono>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

#include "trace_comp.h"

namespace fird {

using namespace fast_tracer_detail;

passes::TracePass fast_tracer_detail::trace_pipeline(
    const vk::Context& ctx, std::array<std::uint32_t, FIRD_SPEC_COUNT> spec,
    std::initializer_list<int> variant, const char* name, std::uint32_t bounce_kind) {
    for (const int id : variant)
        spec[std::size_t(id)] = 1;
    spec[FIRD_SPEC_BOUNCE_KIND] = bounce_kind;
    return passes::TracePass(ctx, fird_spv_trace_comp, name, spec);
}

void FastTracer::dispatch_trace(VkCommandBuffer cb, const RayTable& in, const RayTable& out,
                                const vk::Buffer& counters, const vk::Buffer& farfield,
                                const gpu::TracePush& push, bool record_walk,
                                std::optional<std::uint32_t> groups) {
    const bool paper = params_.hit_mode == gpu::kHitModePaper;
    const passes::TraceBindings b{
        .params = vk::uniform(state().params_buffer),
        .rays_in = vk::storage_texel(in.texels),
        .rays_out = vk::storage_texel(out.texels),
        .counters = vk::storage(counters),
        .pyramid = vk::storage_texel(paper ? state().paper_view : state().refined_view),
        .heights = vk::storage_texel(paper ? state().paper_view : state().corners_view),
        .gradients = vk::texel(state().gradients_view),
        .farfield = vk::storage(farfield),
        .hits = vk::storage(hits_),
        .buckets = vk::storage(order_buckets_),
        .texel_hits = vk::storage(texel_hits_),
        .walk = vk::storage(walk_),
        .profile = vk::storage(profile_),
        .walk_start = vk::storage(state().walk_start),
        .control = vk::storage_texel(state().control.texels),
        .loop = vk::storage(loop_)};
    // The variant that does what the push constants ask and no more (the walk-recording
    // one also records hits; profile counts come from plain runs only).
    const bool diagnostics = push.record_hits != 0u || push.count_texel_hits != 0u;
    if (diagnostics && !record_walk && !trace_diagnostics_pipeline_) {
        trace_diagnostics_pipeline_.emplace(
            trace_pipeline(*ctx_, spec_, {FIRD_SPEC_DIAGNOSTICS}, "fird.trace.diagnostics"));
    }
    const passes::TracePass& p = record_walk   ? *trace_walk_pipeline_
                                 : diagnostics ? *trace_diagnostics_pipeline_
                                 : trace_profile_pipeline_
                                     ? *trace_profile_pipeline_
                                     : trace_pipelines_[push.bounce == 0 ? 0 : 1];
    if (groups)
        p.dispatch(cb, b, push, *groups);
    else
        p.dispatch_indirect(cb, b, push, loop_, gpu::kLoopTraceArgs * 4);
}

void FastTracer::record_bounces(VkCommandBuffer cb, const RayTable& rays, std::uint64_t first,
                                FastRun& run, const BounceRecording& recording) {
    using Hits = BounceRecording::Hits;
    // Every bounce is recorded, each sized on the device by the one before (bounce_args.comp):
    // a bounce without active rays is an indirect dispatch of 0 groups, which costs next
    // to nothing (the skip of empty bounces; with the skip off it runs one workgroup).
    // Bounded by the scene's bounces, like the loop on the device it replaces.
    record_bounce_args(cb, gpu::kArgsFirstBounce, 0);
    const RayTable* in = &rays;
    const RayTable* out = &rays_ping_;
    const std::uint32_t n = passes();
    for (std::uint32_t bounce = 0; bounce < n; ++bounce) {
        // The rays reflected here are ordered by direction for the next bounce, as the
        // rayset is, unless there are too few for the ordering to pay (kOrderMinRays,
        // decided on the device: they are then copied as they are), or every bounce's hits
        // are recorded (a record names the slot its reflected ray was appended at).
        const bool last = bounce + 1 >= n;
        const bool order = !last && recording.hits != Hits::Every;
        BounceProfile& profile = run.bounces[bounce];
        timed(cb, &run.timings.trace_ms, &profile.trace_ms, [&] {
            if (order) {
                vkCmdFillBuffer(cb, order_buckets_.get(), 0, VK_WHOLE_SIZE, 0);
                vk::barrier_all(cb);
            }
            const gpu::TracePush push{
                .first_lo = std::uint32_t(first),
                .first_hi = std::uint32_t(first >> 32),
                .bounce = bounce,
                .final_check = bounce == params_.max_bounces ? 1u : 0u,
                .record_hits =
                    recording.hits == Hits::Every || (recording.hits == Hits::First && bounce == 0)
                        ? 1u
                        : 0u,
                .hits_base = recording.hits == Hits::Every ? bounce * recording.rays : 0u,
                .order_output = order ? 1u : 0u,
                // A path's rays are not the run's: its texel counts are left as they are.
                .count_texel_hits = count_texel_hits_ && recording.hits != Hits::Every ? 1u : 0u,
                .walk_ray = recording.walk_index.value_or(0u),
                .walk_to_box_top = skips_.end_walk_at_reflector_top ? 0u : 1u,
                .walk_from_root = skips_.start_walk_below_source ? 0u : 1u};
            dispatch_trace(cb, *in, *out, counters_, state().farfield_counts, push,
                           recording.walk_index.has_value(), std::nullopt);
            vk::barrier_all(cb);
        });
        if (last) break;
        if (order) {
            // Into the other ping-pong buffer (this bounce's input is consumed).
            const RayTable* spare = (out == &rays_ping_) ? &rays_pong_ : &rays_ping_;
            timed(cb, &run.timings.trace_ms, &profile.order_ms, [&] {
                record_bounce_args(cb, gpu::kArgsNextBounce, bounce + 1);
                record_order(cb, *out, *spare, true);
            });
            in = spare;
        } else {
            // Unordered: the next bounce reads the rays where this one appended them.
            record_bounce_args(cb, gpu::kArgsNextBounce, bounce + 1);
            in = out;
        }
        out = (in == &rays_ping_) ? &rays_pong_ : &rays_ping_;
        // A window sharing the device draws between bounces (the bounce loop is sized on
        // the device, so the pieces need nothing from the host).
        ctx_->yield_queue(cb);
    }
}

} // namespace fird
