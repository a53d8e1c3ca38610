// Calibration on the device: Table 1's mean l2 follows the Monte Carlo prediction, the
// semivariogram's series and steps, --write-steps' scene round trips, bad input refused.
#include <cmath>

#include "calibrate/calibration.hpp"
#include "io/scene_file.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

Scene mirror() {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml");
}

using Calibration = VulkanTest;

// The relative standard deviation of one run's l2, measured over the row's runs: the
// sampling error every check of a mean or of the replicate estimate scales with.
double relative_sd(const RaysRow& r) {
    return std::sqrt(r.var_l2) / r.mean_l2;
}

// The target reflector against itself with independent rays (the `random` sampler): the
// l2 is noise alone and the cells are multinomial, so the prediction shown is the formula
// flux sqrt(sum p (1 - p) (1/n + 1/N)), which the mean follows within 6 % at each count,
// falling as n^-1/2; and the noise measured from pairs of runs (half the mean squared l2
// between two independent traces) is that formula within its sampling error.
TEST_F(Calibration, MeanL2FollowsTheMonteCarloPrediction) {
    Scene s = mirror();
    s.trace.sampler = SamplerKind::Random;
    const RaysTable t = calibrate_rays(
        ctx(), s, {.counts = {2000, 20000, 200000}, .runs = 16, .desired_rays = 4000000});
    EXPECT_EQ(t.sampler, SamplerKind::Random);
    EXPECT_EQ(t.prediction, NoisePrediction::Multinomial);
    ASSERT_EQ(t.rows.size(), 3u);
    for (const RaysRow& r : t.rows) {
        EXPECT_EQ(r.runs, 16u);
        EXPECT_EQ(r.predicted_l2, r.multinomial_l2);
        EXPECT_NEAR(r.mean_l2 / r.predicted_l2, 1.0, 0.06) << r.rays;
        EXPECT_GT(r.var_l2, 0.0);
        // One pair's squared l2 scatters by ~2 relative_sd, so the root of the mean of P
        // pairs by relative_sd / sqrt(P): four of those, plus 1 % for the desired's noise,
        // measured from a single pair (at most n/N = 5 % of the total).
        ASSERT_EQ(r.replicate_pairs, 8u);
        EXPECT_NEAR(r.replicate_l2 / r.multinomial_l2, 1.0,
                    4.0 * relative_sd(r) / std::sqrt(8.0) + 0.01)
            << r.rays;
    }
    EXPECT_GT(t.rows[0].mean_l2, 5.0 * t.rows[2].mean_l2);
    EXPECT_NEAR(t.slope, -0.5, 0.05);
}

// The scenes' default sampler is the stratified one: the prediction shown is its own noise,
// measured from pairs of runs, and the mean l2 follows it within the sampling error of both
// (the mean of 16 runs, the root of the mean of 8 pairs: relative_sd sqrt(1/16 + 1/8),
// four of those plus 1 % for the desired's noise). On this coarse far field (the mirror's
// 180 x 90 cells) the multinomial formula for independent rays lies well above the
// measurement once the strata hold several rays each, so it is no prediction for it.
TEST_F(Calibration, DefaultStratifiedSamplerIsPredictedByItsOwnMeasuredNoise) {
    const Scene s = mirror();
    ASSERT_EQ(s.trace.sampler, SamplerKind::Stratified); // the scene file names none
    const RaysTable t =
        calibrate_rays(ctx(), s, {.counts = {2000, 200000}, .runs = 16, .desired_rays = 4000000});
    EXPECT_EQ(t.sampler, SamplerKind::Stratified);
    EXPECT_EQ(t.prediction, NoisePrediction::Replicate);
    ASSERT_EQ(t.rows.size(), 2u);
    for (const RaysRow& r : t.rows) {
        EXPECT_EQ(r.predicted_l2, r.replicate_l2);
        EXPECT_NEAR(r.mean_l2 / r.predicted_l2, 1.0,
                    4.0 * relative_sd(r) * std::sqrt(1.0 / 16 + 1.0 / 8) + 0.01)
            << r.rays;
        EXPECT_LT(r.mean_l2 / r.multinomial_l2, 1.06) << r.rays; // never noisier
    }
    EXPECT_LT(t.rows[1].mean_l2 / t.rows[1].multinomial_l2, 0.8);
}

TEST_F(Calibration, SemivariogramSeriesStepsAndWriteStepsRoundTrip) {
    const Scene s = mirror();
    const SemivariogramResult r =
        calibrate_semivariogram(ctx(), s, {.parameters = {"sx"}, .points = 13, .rays = 20000});
    ASSERT_EQ(r.parameters.size(), 1u);
    const ParameterSemivariogram& p = r.parameters[0];
    ASSERT_EQ(p.x.size(), 13u);
    EXPECT_DOUBLE_EQ(p.x.front(), -0.3);
    EXPECT_NEAR(p.x.back(), 0.3, 1e-12);
    EXPECT_EQ(p.empirical.lags.size(), 6u);
    EXPECT_EQ(p.empirical.pairs.front(), 12u);
    // l2 is least at the target's sx (0.15) and grows away from it.
    const auto best = std::min_element(p.l2.begin(), p.l2.end()) - p.l2.begin();
    EXPECT_NEAR(p.x[std::size_t(best)], 0.15, 0.051);
    EXPECT_GT(p.model.range, 0.0);
    // The measured noise (8 traces of the target) is Table 1's variance at the same rays:
    // two sample variances of 7 and 15 degrees of freedom agree within [0.1, 5] at 99.9 %.
    const RaysTable t = calibrate_rays(ctx(), s, {.counts = {20000}, .runs = 16});
    ASSERT_GT(t.rows[0].var_l2, 0.0);
    const double ratio = r.noise_variance_l2 / t.rows[0].var_l2;
    EXPECT_GT(ratio, 0.1);
    EXPECT_LT(ratio, 5.0);
    ASSERT_TRUE(p.resolvable_step);
    EXPECT_GT(*p.resolvable_step, 0.0);
    EXPECT_EQ(r.step_rule, StepRule::Resolvable); // the default
    // The resolvable step is judged on the same-rays differences: every probe compared 8
    // raysets on both sides of the target, and those differences are quieter than two
    // fresh-ray traces (sd sqrt(2 sigma^2)) at every lag under half the series' spacing.
    ASSERT_FALSE(p.resolution.empty());
    for (const ResolutionProbe& q : p.resolution) {
        EXPECT_EQ(q.differences, 16u) << q.lag;
        if (q.lag < 0.025 && q.ties < q.differences) {
            EXPECT_LT(q.noise_sd_lm, std::sqrt(2.0 * r.noise_variance_l2)) << q.lag;
        }
    }
    const Scene stepped = scene_with_steps(s, r);
    EXPECT_DOUBLE_EQ(stepped.reflector.optimize.at("sx").step, calibrated_step(p));
    EXPECT_EQ(stepped.reflector.optimize.at("sy"), s.reflector.optimize.at("sy"));
    const Scene back = parse_scene(scene_to_toml(stepped), s.path);
    EXPECT_EQ(back, stepped);
}

TEST_F(Calibration, BadInputIsRefusedNamingIt) {
    const Scene s = mirror();
    const auto message = [&](auto&& call) {
        try {
            call();
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message([&] {
                  calibrate_semivariogram(ctx(), s, {.parameters = {"z0"}});
              }).find("--parameter z0"),
              std::string::npos);
    EXPECT_NE(message([&] { calibrate_semivariogram(ctx(), s, {.points = 2}); }).find("--points 2"),
              std::string::npos);
    EXPECT_NE(message([&] {
                  calibrate_rays(ctx(), s, {.counts = {1000, 0}});
              }).find("0"),
              std::string::npos);
}

} // namespace
} // namespace fird::test
