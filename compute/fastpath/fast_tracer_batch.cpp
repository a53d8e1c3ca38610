// Several candidates in one submission (FastTracer::run_batch): each its own height field
// and far field, traced against the one kept rayset.
#include "fast_tracer.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "fastpath/fast_tracer_internal.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/scene_params.hpp"
#include "vk/check.hpp"

namespace fird {

using namespace fast_tracer_detail;

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
    // A mesh's height field is rasterized in submissions of its own, one reflector at a
    // time (asked of the scene: a fresh tracer has not loaded the mesh yet).
    const bool batchable = one_batch_of_rays && cache_rayset_ && skips_.keep_rayset &&
                           scene_.reflector.family != Family::Mesh && !count_texel_hits_ &&
                           !trace_profile_pipeline_;
    for (const ReflectorDesc& r : reflectors)
        require_family(r);
    // One at a time where a submission cannot hold several; else the first alone when it
    // generates the rayset that the others reuse.
    std::size_t k = 0;
    for (; k < reflectors.size() && (!batchable || rayset_chunks_.empty()); ++k)
        single(k);
    // No more ray-candidates in one submission than one batch of rays may hold: a
    // submission as long as one batch's (a driver's timeout, a window's frame or an
    // interruption waits for no more).
    const std::size_t per_submission = std::size_t(std::clamp<std::uint64_t>(
        submission_rays_ / std::max<std::uint64_t>(scene_.trace.rays, 1), 1, kMaxBatchCandidates));
    // Height fields for the others as memory allows: within three quarters of what the
    // budget (or a quarter of the device-local heap) has left, so that what follows a batch
    // (a fresh evaluator's noise traces, a new seed's rayset) still finds room; and never
    // again past an out-of-memory.
    const std::uint64_t state_bytes = reflector_state_bytes(params_);
    const std::uint64_t limit = ctx_->device_memory_budget()
                                    ? ctx_->device_memory_budget()
                                    : ctx_->limits().device_local_heap_bytes / 4;
    while (k < reflectors.size()) {
        std::size_t m = std::min(per_submission, reflectors.size() - k);
        const std::uint64_t in_use = ctx_->device_memory_in_use();
        const std::uint64_t room = limit > in_use ? (limit - in_use) / 4 * 3 : 0;
        const std::size_t allowed = std::min<std::size_t>(
            batch_states_cap_, batch_states_.size() + std::size_t(room / state_bytes));
        m = std::min(m, allowed + 1);
        while (batch_states_.size() < m - 1) {
            try {
                batch_states_.push_back(make_reflector_state(
                    *ctx_, params_, fmt::format("fird.candidate{}", batch_states_.size() + 1)));
            } catch (const vk::VulkanError& e) {
                if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY &&
                    e.result() != VK_ERROR_OUT_OF_HOST_MEMORY)
                    throw;
                batch_states_cap_ = batch_states_.size();
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
            record_bounces(cb, rays.rays, 0, run);
            record_to_lm(cb, run);
            if (then) {
                timed(cb, &run.timings.compare_ms, nullptr,
                      [&] { then(cb, first + j, state().farfield_lm); });
                vk::barrier_all(cb);
            }
            record_batch_end(cb, j);
            // The next candidate clears the counters and the loop state this copied out.
            vk::barrier_all(cb);
            // A window sharing the queue draws between candidates too (their height
            // fields are not bounded by the batch's rays).
            if (j + 1 < m) ctx_->yield_queue(cb);
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

} // namespace fird
