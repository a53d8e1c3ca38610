// Tracing a search's points with an evaluator built for their stage: the candidate scene
// of each point as Objective::trace builds it. The search's own process and the ranks that
// trace a share of a batch for it under mpirun (compute/distributed) both trace through this,
// so a point's result is the same whichever process traced it.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "evaluation/evaluator.hpp"
#include "optimize/parameter_space.hpp"

namespace fird {

// `evaluator` is at the stage's fidelity with the desired far field set. Points that move
// the source are traced one at a time (each sets its source: no shared rayset); the others
// as one batch (Evaluator::evaluate_batch). Results in the points' order, each with its far
// field when `read_farfields`.
std::vector<CandidateResult> trace_points(Evaluator& evaluator, const Scene& scene,
                                          const ParameterSpace& space,
                                          std::span<const std::vector<double>> points,
                                          bool read_farfields = false);

// A process that traces shares of another's search (a rank under mpirun): the points of a
// stage at its fidelity against the search's desired far field, with the evaluator of the
// last stage it traced kept while the stage's fidelity stays (as the Objective keeps its).
class PointTracer {
  public:
    PointTracer(const vk::Context& ctx, Scene scene);
    std::vector<CandidateResult> trace(const Fidelity& fidelity, Backend backend,
                                       const FarField& desired,
                                       std::span<const std::vector<double>> points);

  private:
    const vk::Context* ctx_;
    Scene scene_;
    ParameterSpace space_;
    std::unique_ptr<Evaluator> evaluator_;
};

} // namespace fird
