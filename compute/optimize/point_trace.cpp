#include "point_trace.hpp"

#include <utility>

namespace fird {

std::vector<CandidateResult> trace_points(Evaluator& evaluator, const Scene& scene,
                                          const ParameterSpace& space,
                                          std::span<const std::vector<double>> points,
                                          bool read_farfields) {
    std::vector<CandidateResult> results;
    if (space.moves_source()) {
        for (const std::vector<double>& x : points) {
            const Scene candidate = space.candidate(scene, x);
            evaluator.set_source(candidate.source);
            results.push_back(std::move(
                evaluator.evaluate_batch(std::span(&candidate.reflector, 1), read_farfields)
                    .front()));
        }
        return results;
    }
    std::vector<ReflectorDesc> reflectors;
    reflectors.reserve(points.size());
    for (const std::vector<double>& x : points)
        reflectors.push_back(space.reflector(scene.reflector, x));
    return evaluator.evaluate_batch(reflectors, read_farfields);
}

PointTracer::PointTracer(const vk::Context& ctx, Scene scene)
    : ctx_(&ctx), scene_(std::move(scene)), space_(parameter_space(scene_)) {}

std::vector<CandidateResult> PointTracer::trace(const Fidelity& fidelity, Backend backend,
                                                const FarField& desired,
                                                std::span<const std::vector<double>> points) {
    if (!evaluator_ || !(evaluator_->fidelity() == fidelity) || evaluator_->backend() != backend) {
        evaluator_.reset(); // one device's worth of buffers at a time
        evaluator_ = std::make_unique<Evaluator>(*ctx_, scene_, fidelity, backend);
        evaluator_->set_desired(desired);
    }
    return trace_points(*evaluator_, scene_, space_, points);
}

} // namespace fird
