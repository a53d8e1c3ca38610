// The tally: clearing the far field and counters, counts to lumens, the small readback of
// each batch and the energy balance of a run.
#include "fast_tracer.hpp"

#include <chrono>
#include <stdexcept>

#include <fmt/format.h>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

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
        vk::barrier_all(cb); // the two counters below over the clear
        vkCmdFillBuffer(cb, counters_.get(), gpu::kCounterEffective * 4, 4,
                        std::uint32_t(*effective));
        vkCmdFillBuffer(cb, counters_.get(), gpu::kCounterDiscarded * 4, 4,
                        std::uint32_t(emitted - *effective));
    }
    vk::barrier_all(cb);
}

void FastTracer::record_to_lm(VkCommandBuffer cb, FastRun& run) {
    const std::uint32_t cells = farfield_cells();
    timed(cb, &run.timings.histogram_ms, nullptr, [&] {
        const passes::ToLmBindings b{.counts = vk::storage_texel(state().farfield_counts_view),
                                     .lumens = vk::storage(state().farfield_lm.values)};
        const gpu::ToLmPush push{.count = cells,
                                 .lm_per_ray = float(run.energy_per_ray_lm),
                                 .layers = params_.farfield_layers,
                                 .reflectance = params_.reflectance};
        // Four cells an invocation (counts_to_lm.comp).
        to_lm_pipeline_.dispatch(cb, b, push, groups((cells + 3) / 4, FIRD_REDUCE_WORKGROUP_SIZE));
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
    for (std::uint32_t r = 0; r <= params_.max_bounces; ++r) {
        t.by_reflections[r] += total(gpu::kCounterByReflections + r);
        t.lost_by_reflections[r] += total(gpu::kCounterLostByReflections + r);
    }
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
    std::uint64_t lost = 0;
    for (const std::uint64_t n : t.lost_by_reflections)
        lost += n;
    if (lost != t.lost)
        throw std::logic_error(fmt::format(
            "fast path lost rays by reflections: {} counted, {} by reflections", t.lost, lost));
}

} // namespace fird
