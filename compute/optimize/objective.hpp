// The objective every search method calls: l2 of a parameter vector at the current stage's
// fidelity, through the evaluation seam. It keeps the history, the best candidate of each
// stage (NLopt's COBYLA returns its last point, not its best), the stop rules (threshold,
// maximum evaluations, interruption) and, for a resumed search, replays the recorded
// candidates instead of tracing them again.
#pragma once

#include <cstdint>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/evaluator.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search_types.hpp"

namespace fird {

// Thrown by Objective::operator() when the search must end; methods let it through.
struct SearchStopped {
    StopReason reason;
};

class Objective {
  public:
    Objective(const vk::Context& ctx, const Scene& scene, ParameterSpace space, FarField desired,
              SearchSettings settings, SearchControl* control, std::vector<Candidate> replay,
              CandidateCallback on_candidate);

    // Starts a stage at `fidelity`. Its evaluator is built when a candidate is first
    // traced, and kept from the previous stage when the fidelity is the same (the rayset
    // too). The threshold applies on the scene's far-field grid only.
    void begin_stage(const std::string& name, const Fidelity& fidelity);

    // The score of x at the current stage: its l2, plus the [optimize] smoothness weight
    // times its bending energy when there is one; an infeasible x is not traced and scores
    // penalty().
    // The same x twice in a stage is answered from the first. Throws SearchStopped.
    double operator()(const std::vector<double>& x);
    // operator() of each x in turn (the same history, memo and stop rules, the same
    // SearchStopped where it would be thrown), with the candidates that need a trace
    // traced a chunk at a time first, several per submission (Evaluator::evaluate_batch).
    // For the points a method polls together (a grid's, a lattice neighbourhood's).
    std::vector<double> evaluate_all(const std::vector<std::vector<double>>& xs);
    // evaluate_all's scores, and each point's far field at the stage's fidelity (empty for
    // an infeasible point): for methods that model the far field itself, not only its
    // distance (Levenberg-Marquardt's Jacobian). A batch traced for the scores keeps its
    // far fields; a point the stage answers from its memo or a resumed search's replay, or
    // that another process traced, is traced again for its far field (with the stage's
    // rays: the same far field) and not recorded again.
    struct ScoredFarFields {
        std::vector<double> scores;
        std::vector<FarField> farfields;
    };
    ScoredFarFields evaluate_all_with_farfields(const std::vector<std::vector<double>>& xs);

    const ParameterSpace& space() const { return space_; }
    const Scene& scene() const { return scene_; }
    // The desired far field, on the scene's grid.
    const FarField& desired() const { return desired_; }
    const SearchSettings& settings() const { return settings_; }
    const std::vector<Candidate>& history() const { return history_; }
    const std::vector<StageSummary>& stages() const { return stages_; }
    const StageSummary& stage() const { return stages_.back(); }
    // The current stage's best feasible candidate, if any.
    const Candidate* stage_best() const;
    std::uint64_t evaluations() const { return history_.size(); }
    // The population generation the candidates recorded from now on belong to (none:
    // not a population's).
    void set_generation(std::optional<std::uint32_t> generation) { generation_ = generation; }
    std::uint64_t remaining() const;
    // The score of an infeasible candidate: above any traced l2 (l2 <= ||desired|| + the
    // largest norm the source's flux can have in the metric: the flux itself for l2),
    // growing with how deep the surface cuts the source or how far it
    // breaks a press's constraint, so model-based methods are pushed back to the feasible
    // side.
    double penalty(const Feasibility& feasibility) const;
    // What an infeasible candidate x scores: penalty(), plus with a smoothness weight the
    // weight times the larger of its bending energy and the stage's largest feasible one
    // (so it stays above every feasible score of the stage).
    double infeasible_score(const Feasibility& feasibility, const std::vector<double>& x,
                            const ReflectorDesc& reflector);

    // Two far fields of x at the current stage's fidelity: with the stage's rays (as its
    // candidates are traced) and with the rays of `seed` instead. A measurement of the
    // stage's noise, not a candidate: nothing is recorded or counted.
    std::pair<FarField, FarField> noise_pair(const std::vector<double>& x, std::uint64_t seed);

  private:
    double trace(const std::vector<double>& x);
    // Traces, in one batch, the points of xs that operator() would trace next (not in the
    // memo, not replayed, feasible, within the evaluation budget) into prefetched_.
    void prefetch(std::span<const std::vector<double>> xs);
    Evaluator& stage_evaluator();
    // The reflector's bending energy with an [optimize] smoothness weight, else 0.
    double smoothness_of(const ReflectorDesc& reflector) const;
    const Candidate& record(Candidate c);

    const vk::Context* ctx_;
    Scene scene_;
    ParameterSpace space_;
    FarField desired_;
    SearchSettings settings_;
    SearchControl* control_;
    std::vector<Candidate> replay_;
    CandidateCallback on_candidate_;

    std::vector<Candidate> history_;
    std::vector<StageSummary> stages_;
    std::map<std::vector<double>, std::uint64_t> stage_memo_; // x -> history index
    std::unique_ptr<Evaluator> evaluator_;
    // Traced by prefetch() and not yet asked for (x -> its result), this stage's only.
    std::map<std::vector<double>, CandidateResult> prefetched_;
    std::optional<std::uint32_t> generation_;
    // While evaluate_all_with_farfields runs: the far fields of the points traced, kept.
    bool capture_farfields_ = false;
    std::map<std::vector<double>, FarField> captured_farfields_;
    // With a smoothness weight: the bending energies of the batch traced ahead, measured on
    // host threads while the device traced it (they do not depend on the trace).
    struct Measured {
        double value = 0.0;
        std::exception_ptr error; // what measuring it threw, rethrown when it is recorded
    };
    std::map<std::vector<double>, Measured> prefetched_energy_;
    double stage_desired_norm_lm_ = 0.0; // in the scene's metric
    double stage_flux_bound_ = 0.0;      // the largest metric norm of the source's flux
    bool threshold_applies_ = false;
    // With a smoothness weight: the stage's largest feasible bending energy, and the
    // energies of its infeasible points (measured once each).
    double stage_largest_energy_ = 0.0;
    std::map<std::vector<double>, double> infeasible_energy_;
};

} // namespace fird
