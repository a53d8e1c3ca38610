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
#include "evaluation/evaluation.hpp"
#include "model/energy_balance.hpp"
#include "model/surface.hpp"

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

const char* backend_name(Backend backend) {
    return backend == Backend::Fast ? "gpu" : "cpu";
}

Evaluator::Evaluator(const vk::Context& ctx, const Scene& scene, const Fidelity& fidelity,
                     Backend backend)
    : ctx_(&ctx), fidelity_(fidelity), scene_(at_fidelity(scene, fidelity)), backend_(backend),
      reduce_(ctx) {
    if (backend == Backend::Fast) tracer_.emplace(ctx, scene_, fidelity.seed);
}

Evaluator::DeviceHeightField Evaluator::device_heightfield() {
    FastTracer& t = fast();
    t.build_paper_heightfield();
    return {.heights = &t.heights_buffer(),
            .gradients = &t.gradients_buffer(),
            .origin_z_mm = t.frame_origin().z,
            .width = t.heightfield_width(),
            .height = t.heightfield_height()};
}

FastTracer& Evaluator::fast() {
    if (!tracer_) throw std::logic_error("Evaluator: the cpu backend has no fast-path tracer");
    return *tracer_;
}
const FastTracer& Evaluator::fast() const {
    if (!tracer_) throw std::logic_error("Evaluator: the cpu backend has no fast-path tracer");
    return *tracer_;
}

void Evaluator::set_desired(const FarField& desired) {
    const FarField* f = &desired;
    FarField coarse;
    if (desired.width != fidelity_.farfield_w || desired.height != fidelity_.farfield_h) {
        coarse = coarsen_farfield(desired, fidelity_.farfield_w, fidelity_.farfield_h);
        f = &coarse;
    }
    // ||desired|| in the metric (the distance to an empty far field), of the values compared.
    FarField compared = *f;
    if (backend_ == Backend::Fast)
        for (double& v : compared.lm)
            v = double(float(v));
    desired_norm_lm_ = farfield_distance(
        compared, FarField{f->width, f->height, std::vector<double>(f->lm.size(), 0.0)}, metric());
    if (backend_ == Backend::Reference) {
        cpu_desired_ = *f; // compared on the host, in double precision
        return;
    }
    const std::vector<float> values(f->lm.begin(), f->lm.end());
    desired_ =
        make_float_table(*ctx_, values.size(), vk::MemoryUse::Device, "fird.evaluator.desired");
    desired_.values.upload(*ctx_, std::span<const float>(values));
    if (metric() != FarFieldMetric::L2)
        row_weights_ = metric_row_weights(*ctx_, metric(), f->width, f->height);
    l2_scratch_ = make_float_table(*ctx_, ReducePass::scratch_floats(values.size()),
                                   vk::MemoryUse::Device, "fird.evaluator.l2.scratch");
    l2_sums_ = vk::Buffer(*ctx_, kL2SumStride, vk::kStorageUsage, vk::MemoryUse::Readback,
                          "fird.evaluator.l2.sums");
}

CandidateResult Evaluator::evaluate(const ReflectorDesc& reflector) {
    return std::move(evaluate_batch(std::span(&reflector, 1)).front());
}

CandidateResult Evaluator::evaluate_on_cpu(const ReflectorDesc& reflector) {
    const auto t0 = std::chrono::steady_clock::now();
    ReferenceResult traced = trace_reference(scene_.source, Surface::make(reflector, scene_.holder),
                                             reference_options(scene_));
    CandidateResult r;
    r.run.tally = traced.tally;
    r.run.energy_per_ray_lm = traced.energy_per_ray_lm;
    r.run.timings.trace_ms = traced.trace_ms;
    r.farfield_lm = energy_balance(traced.tally, traced.energy_per_ray_lm).binned_lm;
    cpu_farfield_ = std::move(traced.farfield);
    if (cpu_desired_) r.l2_lm = farfield_distance(*cpu_farfield_, *cpu_desired_, metric());
    r.wall_ms = ms_since(t0);
    r.run.timings.total_ms = r.wall_ms;
    return r;
}

std::vector<CandidateResult> Evaluator::evaluate_batch(std::span<const ReflectorDesc> reflectors,
                                                       bool read_farfields) {
    if (backend_ == Backend::Reference) {
        std::vector<CandidateResult> results;
        for (const ReflectorDesc& r : reflectors) {
            results.push_back(evaluate_on_cpu(r));
            if (read_farfields) results.back().farfield = *cpu_farfield_;
        }
        traced_ = traced_ || !reflectors.empty();
        return results;
    }
    const auto t0 = std::chrono::steady_clock::now();
    // Candidate k's compare joins the trace's submission (compare() is the same reduction
    // as a submission of its own): its sum of squared differences lands in slot k, read
    // back with the tally.
    // With read_farfields, candidate k's far field is copied out there too, into slot k.
    FastTracer::BatchCompare record_compare;
    const VkDeviceSize farfield_bytes = VkDeviceSize(cells()) * sizeof(float);
    if (read_farfields && farfields_readback_.size() < reflectors.size() * farfield_bytes)
        farfields_readback_ =
            vk::Buffer(*ctx_, reflectors.size() * farfield_bytes, vk::kStorageUsage,
                       vk::MemoryUse::Readback, "fird.evaluator.farfields");
    if (has_desired() && l2_sums_.size() < reflectors.size() * kL2SumStride)
        l2_sums_ = vk::Buffer(*ctx_, reflectors.size() * kL2SumStride, vk::kStorageUsage,
                              vk::MemoryUse::Readback, "fird.evaluator.l2.sums");
    if (has_desired() || read_farfields)
        record_compare = [&](VkCommandBuffer cb, std::size_t k, const FloatTable& farfield) {
            if (has_desired())
                reduce_.record(cb, farfield, &desired_, cells(), l2_scratch_, l2_sums_,
                               k * kL2SumStride, difference());
            if (read_farfields) {
                const VkBufferCopy copy{.dstOffset = k * farfield_bytes, .size = farfield_bytes};
                vkCmdCopyBuffer(cb, farfield.values.get(), farfields_readback_.get(), 1, &copy);
                vk::barrier_to_host(cb);
            }
        };
    std::vector<FastRun> runs = tracer_->run_batch(reflectors, record_compare);
    traced_ = traced_ || !reflectors.empty();
    const double share_ms = ms_since(t0) / double(std::max<std::size_t>(reflectors.size(), 1));
    std::vector<CandidateResult> results(runs.size());
    for (std::size_t k = 0; k < runs.size(); ++k) {
        CandidateResult& r = results[k];
        r.run = std::move(runs[k]);
        r.farfield_lm = energy_balance(r.run.tally, r.run.energy_per_ray_lm).binned_lm;
        if (has_desired()) {
            const auto* sums = static_cast<const std::byte*>(l2_sums_.data());
            float sum = 0.0f;
            std::memcpy(&sum, sums + k * kL2SumStride, sizeof sum);
            r.l2_lm = std::sqrt(std::max(0.0, double(sum)));
        }
        if (read_farfields) {
            const auto* lm =
                static_cast<const float*>(farfields_readback_.data()) + k * std::size_t(cells());
            r.farfield = FarField{fidelity_.farfield_w, fidelity_.farfield_h,
                                  std::vector<double>(lm, lm + cells())};
        }
        r.wall_ms = share_ms;
    }
    return results;
}

void Evaluator::set_seed(std::uint64_t seed) {
    fidelity_.seed = seed;
    scene_.trace.seed = seed;
    if (tracer_) tracer_->set_seed(seed);
}

void Evaluator::set_source(const SourceDesc& source) {
    if (source == scene_.source) return;
    scene_.source = source;
    if (tracer_) tracer_->set_source(source);
}

double Evaluator::compare(double* compare_ms) const {
    if (!traced_ || !has_desired())
        throw std::logic_error("Evaluator::compare: needs a trace and a desired far field");
    if (backend_ == Backend::Reference) {
        const auto t0 = std::chrono::steady_clock::now();
        const double l2 = farfield_distance(*cpu_farfield_, *cpu_desired_, metric());
        if (compare_ms) *compare_ms = ms_since(t0);
        return l2;
    }
    return device_l2(*ctx_, reduce_, tracer_->farfield_lm(), desired_, cells(), compare_ms,
                     difference());
}

double Evaluator::l2_to(const Evaluator& other) const {
    if (cells() != other.cells() || fidelity_.farfield_w != other.fidelity_.farfield_w)
        throw std::invalid_argument("Evaluator::l2_to: far fields of different grids");
    if (!traced_ || !other.traced_) throw std::logic_error("Evaluator::l2_to: nothing traced");
    if (!tracer_ || !other.tracer_)
        return farfield_distance(farfield(), other.farfield(), metric());
    return device_l2(*ctx_, reduce_, tracer_->farfield_lm(), other.tracer_->farfield_lm(), cells(),
                     nullptr, difference());
}

FarField Evaluator::farfield() const {
    if (!tracer_) {
        if (!cpu_farfield_) throw std::logic_error("Evaluator::farfield: nothing traced");
        return *cpu_farfield_;
    }
    return {fidelity_.farfield_w, fidelity_.farfield_h, tracer_->read_farfield()};
}

Evaluation evaluate_fast(const vk::Context& ctx, const Scene& scene,
                         const FastEvaluationOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::uint64_t submissions_before = ctx.submissions();
    const std::uint64_t allocations_before = ctx.memory_allocations().total;
    Evaluator evaluator(ctx, scene, scene_fidelity(scene));
    evaluator.set_profile(options.profile);
    evaluator.set_rayset_kept(false); // one run: nothing reuses it
    const CandidateResult r = evaluator.evaluate(scene.reflector);
    Evaluation e;
    e.backend = "gpu";
    e.device = ctx.summary().name;
    e.tally = r.run.tally;
    e.rays_aborted = r.run.aborted;
    e.energy_per_ray_lm = r.run.energy_per_ray_lm;
    e.timings = r.run.timings;
    if (options.profile) e.bounces = r.run.bounces;
    if (scene.target.kind != TargetDesc::Kind::None) {
        DesiredFarField desired = desired_farfield(ctx, scene, r.farfield_lm);
        evaluator.set_desired(desired.farfield);
        e.l2_lm = evaluator.compare(&e.timings.compare_ms);
        e.metric = evaluator.metric();
        e.target_farfield = std::move(desired.farfield);
    }
    if (options.profile) {
        e.submissions = ctx.submissions() - submissions_before;
        e.device_memory_allocations = ctx.memory_allocations().total - allocations_before;
    }
    e.timings.total_ms = ms_since(t0);
    // A readback for pictures and photometrics, not part of the evaluation's time.
    if (options.read_farfields) e.farfield = evaluator.farfield();
    return e;
}

} // namespace fird
