// Conservation, determinism and Monte Carlo statistics of the reference tracer.
#include <cmath>
#include <numeric>

#include <gtest/gtest.h>

#include "evaluation/evaluation.hpp"
#include "io/scene_file.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {
namespace {

Scene scene(const std::string& name) {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + name);
}

ReferenceResult run(const Scene& s, std::uint64_t rays, std::uint64_t seed,
                    SamplerKind sampler = SamplerKind::Random, std::uint32_t ffw = 360,
                    std::uint32_t ffh = 180, unsigned threads = 0) {
    return trace_reference(s.source, Surface::make(s.reflector, s.holder),
                           {.rays = rays,
                            .seed = seed,
                            .sampler = sampler,
                            .max_bounces = s.trace.max_bounces,
                            .bounce_policy = s.trace.bounce_policy,
                            .farfield_w = ffw,
                            .farfield_h = ffh,
                            .threads = threads});
}

class EnergyBalance : public ::testing::TestWithParam<std::string> {};

TEST_P(EnergyBalance, EveryEmittedRayIsAccountedForExactly) {
    for (BouncePolicy policy : {BouncePolicy::Paper, BouncePolicy::Strict}) {
        Scene s = scene(GetParam());
        s.trace.bounce_policy = policy;
        const auto r = run(s, 30000, 4);
        const RayTally& t = r.tally;
        EXPECT_EQ(t.emitted, t.discarded + t.direct + t.farfield + t.lost);
        EXPECT_EQ(t.farfield,
                  std::accumulate(t.by_reflections.begin(), t.by_reflections.end(), 0ull));
        EXPECT_EQ(t.by_reflections[0], 0u) << "direct light never reaches the far field";
        EXPECT_NEAR(r.farfield.total_lm(), double(t.farfield) * r.energy_per_ray_lm, 1e-9);
        EXPECT_EQ(t.below_surface, 0u);
        if (policy == BouncePolicy::Paper) {
            EXPECT_EQ(t.lost, 0u);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EnergyBalance,
                         ::testing::Values("model_a.toml", "model_b.toml", "model_c.toml",
                                           "test/flat_mirror.toml",
                                           "test/focused_paraboloid.toml"));

TEST(ReferenceDeterminism, SameSeedSameHistogramWhateverTheThreadCount) {
    const Scene s = scene("model_c.toml");
    const auto a = run(s, 40000, 17, SamplerKind::Random, 360, 180, 1);
    const auto b = run(s, 40000, 17, SamplerKind::Random, 360, 180, 2);
    const auto c = run(s, 40000, 17, SamplerKind::Random, 360, 180, 7);
    EXPECT_EQ(a.farfield.lm, b.farfield.lm);
    EXPECT_EQ(a.farfield.lm, c.farfield.lm);
    const auto d = run(s, 40000, 18);
    EXPECT_NE(a.farfield.lm, d.farfield.lm);
}

// Two independent N-ray runs differ by l2 with E[l2^2] = 2 F^2 sum p_i (1 - p_i) / N,
// p_i the chance that a ray lands in cell i: the noise falls as 1/sqrt(N).
TEST(ReferenceStatistics, SeedToSeedNoiseScalesAsOneOverSqrtNOverTwoDecades) {
    const Scene s = scene("model_a.toml");
    const double flux = s.source.flux_lm;
    const auto dense = run(s, 1000000, 1000);
    double sum_p = 0.0;
    for (double v : dense.farfield.lm) {
        const double p = v / flux;
        sum_p += p * (1.0 - p);
    }
    std::vector<double> log_n, log_l2;
    for (std::uint64_t n : {1000ull, 10000ull, 100000ull}) {
        double mean_sq = 0.0;
        constexpr int kPairs = 6;
        for (int k = 0; k < kPairs; ++k) {
            const double l2 =
                l2_distance(run(s, n, 2 * k + 1).farfield, run(s, n, 2 * k + 2).farfield);
            mean_sq += l2 * l2 / kPairs;
        }
        const double predicted = flux * std::sqrt(2.0 * sum_p / double(n));
        // 6 pairs: the mean square is within ~35 % of its expectation (chi-square-like).
        EXPECT_NEAR(std::sqrt(mean_sq) / predicted, 1.0, 0.2) << n << " rays";
        log_n.push_back(std::log(double(n)));
        log_l2.push_back(0.5 * std::log(mean_sq));
    }
    const double slope = (log_l2.back() - log_l2.front()) / (log_n.back() - log_n.front());
    EXPECT_NEAR(slope, -0.5, 0.06);
}

TEST(ReferenceStatistics, SobolIsCloserToTheConvergedFarFieldThanRandomAtEqualRays) {
    const Scene s = scene("model_a.toml");
    constexpr std::uint32_t kW = 90, kH = 45; // 4-degree cells: variance, not binning, dominates
    // Measured on this scene (mean over 4 seeds): Sobol's l2 is 6 % below random's at
    // 2^12 rays and 20 % below at 2^18; the cell indicator is discontinuous, so the gain
    // is modest. At 2^18 over 4 seeds the gap is several standard errors.
    const auto reference = run(s, 8000000, 77, SamplerKind::Random, kW, kH);
    double random_sq = 0.0, sobol_sq = 0.0;
    for (std::uint64_t seed : {1ull, 2ull, 3ull, 4ull}) {
        const double r = l2_distance(run(s, 1 << 18, seed, SamplerKind::Random, kW, kH).farfield,
                                     reference.farfield);
        const double q = l2_distance(run(s, 1 << 18, seed, SamplerKind::Sobol, kW, kH).farfield,
                                     reference.farfield);
        random_sq += r * r;
        sobol_sq += q * q;
    }
    EXPECT_LT(std::sqrt(sobol_sq), std::sqrt(random_sq));
}

TEST(ReferenceTarget, TargetTracedWithAnIndependentSeedGivesNoiseLevelL2) {
    // The target of model A is the reflector itself when the parameters match.
    Scene s = scene("model_a.toml");
    s.reflector.parameters = target_reflector(s).parameters;
    s.trace.rays = 400000;
    s.trace.farfield_w = 360;
    s.trace.farfield_h = 180;
    const Evaluation e = evaluate_reference(s);
    ASSERT_TRUE(e.l2_lm);
    EXPECT_GT(*e.l2_lm, 0.0) << "the target must use another seed";
    Scene far = s;
    far.reflector.parameters["fx"] = 11.0;
    EXPECT_GT(*evaluate_reference(far).l2_lm, 3.0 * *e.l2_lm);
}

} // namespace
} // namespace fird
