#include "evaluator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "evaluation/desired_farfield.hpp"

namespace fird {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

Fidelity scene_fidelity(const Scene& s) {
    const TraceSettings& t = s.trace;
    return {.rays = t.rays,
            .seed = t.seed,
            .farfield_w = t.farfield_w,
            .farfield_h = t.farfield_h,
            .heightfield_w = t.heightfield_w,
            .heightfield_h = t.heightfield_h};
}

Scene at_fidelity(Scene s, const Fidelity& f) {
    s.trace.rays = f.rays;
    s.trace.seed = f.seed;
    s.trace.farfield_w = f.farfield_w;
    s.trace.farfield_h = f.farfield_h;
    s.trace.heightfield_w = f.heightfield_w;
    s.trace.heightfield_h = f.heightfield_h;
    return s;
}

Evaluator::Evaluator(const vk::Context& ctx, const Scene& scene, const Fidelity& fidelity)
    : ctx_(&ctx), fidelity_(fidelity), scene_(at_fidelity(scene, fidelity)),
      tracer_(ctx, scene_, fidelity.seed), reduce_(ctx) {}

void Evaluator::set_desired(const FarField& desired) {
    const FarField* f = &desired;
    FarField coarse;
    if (desired.width != fidelity_.farfield_w || desired.height != fidelity_.farfield_h) {
        coarse = coarsen_farfield(desired, fidelity_.farfield_w, fidelity_.farfield_h);
        f = &coarse;
    }
    const std::vector<float> values(f->lm.begin(), f->lm.end());
    desired_ = vk::Buffer(*ctx_, values.size() * 4, vk::kStorageUsage, vk::MemoryUse::Device,
                          "fird.evaluator.desired");
    desired_.upload(*ctx_, std::span<const float>(values));
    l2_scratch_ = vk::Buffer(*ctx_, ReducePass::scratch_bytes(values.size()), vk::kStorageUsage,
                             vk::MemoryUse::Device, "fird.evaluator.l2.scratch");
    l2_sums_ = vk::Buffer(*ctx_, kL2SumStride, vk::kStorageUsage, vk::MemoryUse::Readback,
                          "fird.evaluator.l2.sums");
    double sum = 0.0;
    for (float v : values)
        sum += double(v) * double(v);
    desired_norm_lm_ = std::sqrt(sum);
}

CandidateResult Evaluator::evaluate(const ReflectorDesc& reflector) {
    return std::move(evaluate_batch(std::span(&reflector, 1)).front());
}

std::vector<CandidateResult> Evaluator::evaluate_batch(std::span<const ReflectorDesc> reflectors) {
    const auto t0 = std::chrono::steady_clock::now();
    // Candidate k's compare joins the trace's submission (compare() is the same reduction
    // as a submission of its own): its sum of squared differences lands in slot k, read
    // back with the tally.
    FastTracer::BatchCompare record_compare;
    if (has_desired()) {
        if (l2_sums_.size() < reflectors.size() * kL2SumStride)
            l2_sums_ = vk::Buffer(*ctx_, reflectors.size() * kL2SumStride, vk::kStorageUsage,
                                  vk::MemoryUse::Readback, "fird.evaluator.l2.sums");
        record_compare = [&](VkCommandBuffer cb, std::size_t k, const vk::Buffer& farfield) {
            reduce_.record(cb, farfield, &desired_, cells(), l2_scratch_, l2_sums_,
                           k * kL2SumStride);
        };
    }
    std::vector<FastRun> runs = tracer_.run_batch(reflectors, record_compare);
    traced_ = true;
    const double share_ms = ms_since(t0) / double(std::max<std::size_t>(reflectors.size(), 1));
    std::vector<CandidateResult> results(runs.size());
    for (std::size_t k = 0; k < runs.size(); ++k) {
        CandidateResult& r = results[k];
        r.run = std::move(runs[k]);
        r.farfield_lm = double(r.run.tally.farfield) * r.run.energy_per_ray_lm;
        if (has_desired()) {
            const auto* sums = static_cast<const std::byte*>(l2_sums_.data());
            float sum = 0.0f;
            std::memcpy(&sum, sums + k * kL2SumStride, sizeof sum);
            r.l2_lm = std::sqrt(std::max(0.0, double(sum)));
        }
        r.wall_ms = share_ms;
    }
    return results;
}

void Evaluator::set_seed(std::uint64_t seed) {
    fidelity_.seed = seed;
    scene_.trace.seed = seed;
    tracer_.set_seed(seed);
}

double Evaluator::compare(double* compare_ms) const {
    if (!traced_ || !has_desired())
        throw std::logic_error("Evaluator::compare: needs a trace and a desired far field");
    return device_l2(*ctx_, reduce_, tracer_.farfield_lm(), desired_, cells(), compare_ms);
}

double Evaluator::l2_to(const Evaluator& other) const {
    if (cells() != other.cells() || fidelity_.farfield_w != other.fidelity_.farfield_w)
        throw std::invalid_argument("Evaluator::l2_to: far fields of different grids");
    if (!traced_ || !other.traced_) throw std::logic_error("Evaluator::l2_to: nothing traced");
    return device_l2(*ctx_, reduce_, tracer_.farfield_lm(), other.tracer_.farfield_lm(), cells());
}

FarField Evaluator::farfield() const {
    return {fidelity_.farfield_w, fidelity_.farfield_h, tracer_.read_farfield()};
}

Evaluation evaluate_fast(const vk::Context& ctx, const Scene& scene,
                         const FastEvaluationOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t submissions_before = ctx.submissions();
    const std::uint64_t allocations_before = ctx.memory_allocations().total;
    Evaluator evaluator(ctx, scene, scene_fidelity(scene));
    evaluator.tracer().set_profile(options.profile);
    evaluator.tracer().set_rayset_kept(false); // one run: nothing reuses it
    const CandidateResult r = evaluator.evaluate(scene.reflector);
    Evaluation e;
    e.backend = "gpu";
    e.device = ctx.summary().name;
    e.tally = r.run.tally;
    e.rays_aborted = r.run.aborted;
    e.energy_per_ray_lm = r.run.energy_per_ray_lm;
    e.timings = r.run.timings;
    if (options.profile) e.bounces = r.run.bounces;
    if (options.read_farfields) e.farfield = evaluator.farfield();
    if (scene.target.kind != TargetDesc::Kind::None) {
        DesiredFarField desired = desired_farfield(ctx, scene, r.farfield_lm);
        evaluator.set_desired(desired.farfield);
        e.l2_lm = evaluator.compare(&e.timings.compare_ms);
        e.target_farfield = std::move(desired.farfield);
    }
    if (options.profile) {
        e.submissions = ctx.submissions() - submissions_before;
        e.device_memory_allocations = ctx.memory_allocations().total - allocations_before;
    }
    e.timings.total_ms = ms_since(t0);
    return e;
}

} // namespace fird
