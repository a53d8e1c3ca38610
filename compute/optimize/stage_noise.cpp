// What noise alone leaves in a stage's l2: one reflector traced with the stage's rays and
// with an independent stream at the same fidelity. auto's confirm stage uses it to decide
// whether to poll pairs of steps, the refine below the step whether to start again.
#include <cmath>

#include "methods.hpp"
#include "optimize/search.hpp"

namespace fird {

namespace {

// The noise pair's stream (search.cpp's streams: stages from 0, the final and noise runs
// at 1000 and 1001).
constexpr std::uint64_t kStageNoiseStream = 1002;

// Standard deviations of noise an l2 may lie above the measured noise l2 and still be
// called noise: one-sided, 2 leaves a 2.3 % chance of calling noise a mismatch (costing
// candidates, never accuracy).
constexpr double kNoiseSigmas = 2.0;

} // namespace

// `a` and `b` are one reflector traced with two independent streams, so their per-cell
// differences d are noise alone. l2 = sqrt(S), S = sum d^2. With cells independent and
// d_i ~ N(0, v_i): var S = 2 sum v_i^2 and E d^4 = 3 v^2, so sd(S) ~ sqrt(2/3 sum d^4) and
// sd(l2) ~ sd(S) / (2 S) * l2. The stage's l2 (candidate against the desired) carries
// noise of its own, independent of this pair's: the limit allows kNoiseSigmas of the
// difference of two such l2 (sqrt 2 sd). At the optimum the candidate's l2 to a desired
// traced with at least the stage's rays is at most this pair's in expectation (a
// noise-free desired gives 1/sqrt 2 of it), so the limit errs towards calling a mismatch.
ConfirmNoise stage_noise(Objective& f, const std::vector<double>& x, double l2_lm) {
    const std::uint64_t avoid = streams_avoid(f.scene());
    const auto [a, b] = f.noise_pair(x, stream_seed(f.settings().seed, kStageNoiseStream, avoid));
    // In the scene's metric: each cell's squared difference weighted (w = 1 for l2), the
    // variance of S = sum w d^2 then 2 sum w^2 v^2, so s4 sums (w d^2)^2.
    const FarFieldMetric metric = f.scene().optimize.metric;
    double s2 = 0.0, s4 = 0.0;
    for (std::size_t i = 0; i < a.lm.size(); ++i) {
        const double w = metric_cell_weight(metric, std::uint32_t(i / a.width), a.width, a.height);
        const double d2 = (double(a.lm[i]) - double(b.lm[i])) * (double(a.lm[i]) - double(b.lm[i]));
        s2 += w * d2;
        s4 += w * w * d2 * d2;
    }
    const double noise = std::sqrt(s2);
    const double relative_sd = s2 > 0.0 ? std::sqrt(2.0 / 3.0 * s4) / (2.0 * s2) : 0.0;
    return {.l2_lm = l2_lm,
            .noise_l2_lm = noise,
            .limit_lm = noise * (1.0 + kNoiseSigmas * std::sqrt(2.0) * relative_sd)};
}

} // namespace fird
