#include "objective.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <limits>
#include <set>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "model/press_measures.hpp"
#include "model/surface.hpp"
#include "optimize/point_trace.hpp"

namespace fird {

Objective::Objective(const vk::Context& ctx, const Scene& scene, ParameterSpace space,
                     FarField desired, SearchSettings settings, SearchControl* control,
                     std::vector<Candidate> replay, CandidateCallback on_candidate)
    : ctx_(&ctx), scene_(scene), space_(std::move(space)), desired_(std::move(desired)),
      settings_(std::move(settings)), control_(control), replay_(std::move(replay)),
      on_candidate_(std::move(on_candidate)) {}

void Objective::begin_stage(const std::string& name, const Fidelity& fidelity) {
    if (evaluator_ && !(evaluator_->fidelity() == fidelity)) evaluator_.reset();
    stages_.push_back({.name = name, .fidelity = fidelity});
    stage_memo_.clear();
    prefetched_.clear();
    prefetched_energy_.clear();
    infeasible_energy_.clear();
    stage_largest_energy_ = 0.0;
    threshold_applies_ = settings_.threshold_lm > 0.0 && fidelity.farfield_w == desired_.width &&
                         fidelity.farfield_h == desired_.height;
    const FarField coarse =
        fidelity.farfield_w == desired_.width && fidelity.farfield_h == desired_.height
            ? desired_
            : coarsen_farfield(desired_, fidelity.farfield_w, fidelity.farfield_h);
    // ||desired|| and the most a far field of the source's flux can measure, in the metric:
    // a weighted norm of lumens summing to F is at most F sqrt(largest weight) (all of it
    // in one cell of the heaviest row), 1 for l2.
    const FarFieldMetric metric = scene_.optimize.metric;
    stage_desired_norm_lm_ = farfield_distance(
        coarse, FarField{coarse.width, coarse.height, std::vector<double>(coarse.lm.size(), 0.0)},
        metric);
    double heaviest = 0.0;
    for (std::uint32_t row = 0; row < coarse.height; ++row)
        heaviest = std::max(heaviest, metric_cell_weight(metric, row, coarse.width, coarse.height));
    stage_flux_bound_ = scene_.source.flux_lm * std::sqrt(heaviest);
}

const Candidate* Objective::stage_best() const {
    const auto& best = stage().best;
    return best ? &history_[*best] : nullptr;
}

std::uint64_t Objective::remaining() const {
    return settings_.max_evaluations > history_.size() ? settings_.max_evaluations - history_.size()
                                                       : 0;
}

double Objective::penalty(const Feasibility& f) const {
    const double dz = scene_.holder.max_mm.z - scene_.holder.min_mm.z;
    return (stage_desired_norm_lm_ + stage_flux_bound_) *
           (1.0 + std::max(0.0, -f.clearance_mm) / dz + f.violation);
}

double Objective::operator()(const std::vector<double>& x) {
    if (stages_.empty()) throw std::logic_error("Objective: no stage begun");
    if (const auto it = stage_memo_.find(x); it != stage_memo_.end()) {
        const Candidate& c = history_[it->second];
        if (c.feasible) return c.score;
        const Scene candidate = space_.candidate(scene_, x);
        return infeasible_score(candidate_feasibility(candidate, candidate.reflector), x,
                                candidate.reflector);
    }
    if (control_) {
        while (control_->pause.load() && !control_->stop.load())
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        if (control_->stop.load()) throw SearchStopped{StopReason::Interrupted};
    }
    if (history_.size() >= settings_.max_evaluations)
        throw SearchStopped{StopReason::MaxEvaluations};
    const double value = trace(x);
    // The threshold is on the metric (the l2), whatever the smoothness adds to the score.
    if (threshold_applies_ && history_.back().feasible &&
        history_.back().l2_lm < settings_.threshold_lm)
        throw SearchStopped{StopReason::Threshold};
    return value;
}

double Objective::trace(const std::vector<double>& x) {
    const auto t0 = std::chrono::steady_clock::now();
    Candidate c{.index = history_.size(), .stage = std::uint32_t(stages_.size() - 1), .x = x};
    const Scene candidate = space_.candidate(scene_, x);
    const ReflectorDesc& reflector = candidate.reflector;
    // A point traced ahead was found feasible then (its press measures are not taken twice).
    const Feasibility f =
        prefetched_.contains(x) ? Feasibility{} : candidate_feasibility(candidate, reflector);
    c.feasible = f.feasible;
    c.l2_lm = c.smoothness = c.score = std::numeric_limits<double>::quiet_NaN();
    if (c.index < replay_.size()) {
        // A resumed search: the recorded candidate must be this one, or the search differs.
        const Candidate& r = replay_[c.index];
        if (r.stage != c.stage || r.x != x || r.feasible != c.feasible)
            throw std::runtime_error(fmt::format(
                "history row {} does not match the resumed search (its scene or settings "
                "changed since it was recorded{})",
                c.index,
                scene_.optimize.height_sampling == HeightSampling::Modes && generation_
                    ? "; a population search over a height grid recorded before its heights "
                      "were sampled as modes resumes with [optimize] height_sampling = "
                      "\"independent\" in its scene.toml"
                    : ""));
        c.l2_lm = r.l2_lm;
        c.smoothness = r.smoothness;
        c.score = r.score;
        c.ms = r.ms;
        c.replayed = true;
    } else if (c.feasible) {
        CandidateResult result;
        bool batched = false;
        if (const auto it = prefetched_.find(x); it != prefetched_.end()) {
            result = std::move(it->second);
            prefetched_.erase(it);
            batched = true;
        } else {
            if (space_.moves_source()) stage_evaluator().set_source(candidate.source);
            result = stage_evaluator().evaluate(reflector);
            // Traced alone: its far field is the evaluator's last.
            if (capture_farfields_) result.farfield = stage_evaluator().farfield();
        }
        if (capture_farfields_ && result.farfield)
            captured_farfields_.insert_or_assign(x, std::move(*result.farfield));
        c.l2_lm = *result.l2_lm;
        if (!std::isfinite(c.l2_lm))
            throw std::runtime_error(fmt::format(
                "candidate {}: the far field's l2 is not finite ({})", c.index, c.l2_lm));
        if (const auto e = prefetched_energy_.find(x); e != prefetched_energy_.end()) {
            const Measured energy = e->second;
            prefetched_energy_.erase(e);
            if (energy.error) std::rethrow_exception(energy.error); // as smoothness_of would
            c.smoothness = energy.value;
        } else {
            c.smoothness = smoothness_of(reflector);
        }
        c.score = candidate_score(c.l2_lm, c.smoothness, scene_.optimize);
        // A batch's candidate adds its share of the batch's time to its own checks.
        c.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                   .count() +
               (batched ? result.wall_ms : 0.0);
    }
    const Candidate& stored = record(std::move(c));
    return stored.feasible ? stored.score : infeasible_score(f, x, reflector);
}

std::vector<double> Objective::evaluate_all(const std::vector<std::vector<double>>& xs) {
    std::vector<double> out;
    out.reserve(xs.size());
    // A chunk a submission's worth: an interruption waits for one chunk at most.
    // Across processes, a submission's worth for each.
    const std::size_t chunk =
        FastTracer::kMaxBatchCandidates * std::max<std::size_t>(settings_.distributed.processes, 1);
    for (std::size_t first = 0; first < xs.size(); first += chunk) {
        const std::size_t n = std::min(chunk, xs.size() - first);
        prefetch(std::span(xs).subspan(first, n));
        for (std::size_t k = first; k < first + n; ++k)
            out.push_back((*this)(xs[k]));
    }
    return out;
}

Objective::ScoredFarFields
Objective::evaluate_all_with_farfields(const std::vector<std::vector<double>>& xs) {
    struct Capture {
        Objective& f;
        Capture(Objective& o) : f(o) {
            f.capture_farfields_ = true;
            f.captured_farfields_.clear();
        }
        ~Capture() {
            f.capture_farfields_ = false;
            f.captured_farfields_.clear();
        }
    } capture(*this);
    ScoredFarFields out{.scores = evaluate_all(xs), .farfields = {}};
    // The feasible points whose far fields this call did not trace: traced again, a
    // submission's worth at a time, unrecorded.
    std::vector<std::vector<double>> again;
    for (const std::vector<double>& x : xs)
        if (!captured_farfields_.contains(x) && history_[stage_memo_.at(x)].feasible &&
            std::find(again.begin(), again.end(), x) == again.end())
            again.push_back(x);
    for (std::size_t first = 0; first < again.size(); first += FastTracer::kMaxBatchCandidates) {
        const std::size_t n = std::min(FastTracer::kMaxBatchCandidates, again.size() - first);
        const auto points = std::span(again).subspan(first, n);
        std::vector<CandidateResult> traced =
            trace_points(stage_evaluator(), scene_, space_, points, true);
        for (std::size_t k = 0; k < n; ++k)
            captured_farfields_.insert_or_assign(points[k], std::move(*traced[k].farfield));
    }
    for (const std::vector<double>& x : xs) {
        const auto it = captured_farfields_.find(x);
        out.farfields.push_back(it == captured_farfields_.end() ? FarField{} : it->second);
    }
    return out;
}

void Objective::prefetch(std::span<const std::vector<double>> xs) {
    if (stages_.empty() || (control_ && (control_->stop.load() || control_->pause.load())))
        return; // operator() stops or waits before any trace
    // The reference backend traces a batch one candidate after another: tracing ahead
    // would only delay a stop or a pause by up to a chunk of seconds-long traces. A batch
    // shares one rayset: candidates that move the source are traced one at a time.
    // Shared among processes (SearchSettings::distributed), the batch goes ahead whatever
    // the backend: each process traces its share, one at a time where the source moves.
    const bool distributed = bool(settings_.distributed.trace);
    if (!distributed && (settings_.backend == Backend::Reference || space_.moves_source())) return;
    // The history index each x will take, as operator() assigns them in turn.
    std::uint64_t index = history_.size();
    std::set<std::vector<double>> seen;
    std::vector<std::vector<double>> keys;
    for (const std::vector<double>& x : xs) {
        if (stage_memo_.contains(x) || !seen.insert(x).second) continue; // answered from the memo
        if (index >= settings_.max_evaluations) break;
        // Replayed, or traced ahead already: an index of the history, no trace.
        if (index++ < replay_.size() || prefetched_.contains(x)) continue;
        const Feasibility f =
            space_.moves_source()
                ? candidate_feasibility(space_.candidate(scene_, x),
                                        space_.reflector(scene_.reflector, x))
                : candidate_feasibility(scene_, space_.reflector(scene_.reflector, x));
        if (!f.feasible) continue;
        keys.push_back(x);
    }
    if (keys.size() < 2) return; // traced when asked for, as before
    // Should the batch fail (a lost device, a broken energy balance), none of its points is
    // recorded, where one at a time the earlier ones would have been: a resumed search
    // traces them again.
    const auto trace_here = [this](std::span<const std::vector<double>> points) {
        return trace_points(stage_evaluator(), scene_, space_, points, capture_farfields_);
    };
    // The batch's bending energies (a weighted search), measured on up to a core's worth of
    // host threads while the device traces the batch (one after another, before, they
    // waited for it), each exactly as alone; an error is kept for its candidate.
    std::vector<Measured> energies(scene_.optimize.smoothness > 0.0 ? keys.size() : 0);
    std::vector<ReflectorDesc> shapes;
    for (std::size_t k = 0; k < energies.size(); ++k)
        shapes.push_back(space_.reflector(scene_.reflector, keys[k]));
    std::atomic<std::size_t> next_energy{0};
    std::vector<std::future<void>> measuring;
    const std::size_t threads =
        std::min<std::size_t>(energies.size(), std::max(1u, std::thread::hardware_concurrency()));
    for (std::size_t t = 0; t < threads; ++t)
        measuring.push_back(std::async(std::launch::async, [&] {
            for (std::size_t k; (k = next_energy++) < energies.size();) {
                try {
                    energies[k].value = smoothness_of(shapes[k]);
                } catch (...) {
                    energies[k].error = std::current_exception();
                }
            }
        }));
    std::vector<CandidateResult> results =
        distributed ? settings_.distributed.trace(StageBatch{.fidelity = stage().fidelity,
                                                             .desired = desired_,
                                                             .points = keys,
                                                             .trace_here = trace_here})
                    : trace_here(keys);
    for (std::future<void>& m : measuring)
        m.get();
    for (std::size_t k = 0; k < keys.size(); ++k) {
        prefetched_.emplace(keys[k], std::move(results[k]));
        if (!energies.empty()) prefetched_energy_.emplace(keys[k], energies[k]);
    }
}

double Objective::infeasible_score(const Feasibility& f, const std::vector<double>& x,
                                   const ReflectorDesc& reflector) {
    if (!(scene_.optimize.smoothness > 0.0)) return penalty(f);
    // Above every feasible score of the stage: the penalty bounds the l2, and the energy
    // added is at least the largest a feasible candidate of the stage had (a shape the
    // family cannot make has none of its own). Measured once per point of a stage.
    auto it = infeasible_energy_.find(x);
    if (it == infeasible_energy_.end()) {
        double energy = 0.0;
        try {
            energy = smoothness_of(reflector);
        } catch (const std::exception&) {
        }
        it = infeasible_energy_.emplace(x, energy).first;
    }
    return penalty(f) + scene_.optimize.smoothness * std::max(it->second, stage_largest_energy_);
}

double Objective::smoothness_of(const ReflectorDesc& reflector) const {
    if (!(scene_.optimize.smoothness > 0.0)) return 0.0;
    const double energy = search_bending_energy(Surface::make(reflector, scene_.holder));
    if (!std::isfinite(energy))
        throw std::runtime_error(fmt::format(
            "[optimize] smoothness: the reflector's bending energy is not finite ({})", energy));
    return energy;
}

Evaluator& Objective::stage_evaluator() {
    if (!evaluator_) {
        evaluator_ =
            std::make_unique<Evaluator>(*ctx_, scene_, stage().fidelity, settings_.backend);
        evaluator_->set_desired(desired_);
    }
    return *evaluator_;
}

std::pair<FarField, FarField> Objective::noise_pair(const std::vector<double>& x,
                                                    std::uint64_t seed) {
    if (stages_.empty()) throw std::logic_error("Objective: no stage begun");
    const Scene candidate = space_.candidate(scene_, x);
    if (space_.moves_source()) stage_evaluator().set_source(candidate.source);
    (void)stage_evaluator().evaluate(candidate.reflector);
    Fidelity other = stage().fidelity;
    other.seed = seed;
    Evaluator fresh(*ctx_, candidate, other, settings_.backend);
    (void)fresh.evaluate(candidate.reflector);
    return {evaluator_->farfield(), fresh.farfield()};
}

const Candidate& Objective::record(Candidate c) {
    c.generation = generation_;
    StageSummary& s = stages_.back();
    ++s.evaluations;
    if (!c.feasible) ++s.infeasible;
    if (!c.replayed && c.feasible) {
        ++s.traced;
        s.traced_ms += c.ms;
    }
    if (c.feasible && c.smoothness > stage_largest_energy_) stage_largest_energy_ = c.smoothness;
    if (c.feasible && (!s.best || c.score < s.best_score)) {
        s.best = c.index;
        s.best_l2_lm = c.l2_lm;
        s.best_score = c.score;
    }
    stage_memo_[c.x] = c.index;
    history_.push_back(std::move(c));
    if (on_candidate_) on_candidate_(history_.back(), s);
    return history_.back();
}

} // namespace fird
