// The semivariogram estimator against hand-computed series, and each model's fit against
// synthetic Gaussian processes drawn from that model (known nugget, sill and range).
#include <cmath>
#include <random>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "calibrate/calibration.hpp"
#include "calibrate/semivariogram.hpp"

namespace fird::test {
namespace {

TEST(Semivariogram, MatheronEstimatorMatchesTheSeriesByHand) {
    const auto e = empirical_semivariogram({1, 3, 2, 5, 4, 8}, 0.5);
    ASSERT_EQ(e.lags.size(), 2u); // up to half the span: (6 - 1) / 2 lags
    EXPECT_DOUBLE_EQ(e.lags[0], 0.5);
    EXPECT_DOUBLE_EQ(e.lags[1], 1.0);
    EXPECT_DOUBLE_EQ(e.gamma[0], 31.0 / 10.0); // (4 + 1 + 9 + 1 + 16) / (2 * 5)
    EXPECT_DOUBLE_EQ(e.gamma[1], 18.0 / 8.0);  // (1 + 4 + 4 + 9) / (2 * 4)
    EXPECT_EQ(e.pairs, (std::vector<std::size_t>{5, 4}));
}

TEST(Semivariogram, PointsNotMeasuredTakeNoPartAndFewPairsStillCount) {
    const double nan = std::nan("");
    const auto e = empirical_semivariogram({1, nan, 2, 5, 4, 8, 7}, 1.0);
    ASSERT_EQ(e.lags.size(), 3u);
    EXPECT_EQ(e.pairs, (std::vector<std::size_t>{4, 4, 3}));
    EXPECT_DOUBLE_EQ(e.gamma[0], 27.0 / 8.0);
    EXPECT_DOUBLE_EQ(e.gamma[1], 23.0 / 8.0);
    EXPECT_DOUBLE_EQ(e.gamma[2], 56.0 / 6.0);
    EXPECT_THROW(empirical_semivariogram({1, 2}, 1.0), std::invalid_argument);
}

// The mean empirical semivariogram of `realizations` seeded draws of a Gaussian process
// on 101 points 0.1 apart whose covariance is sill - gamma(h) of the given model.
EmpiricalSemivariogram synthetic(const VariogramFit& truth, int realizations) {
    constexpr int kPoints = 101;
    constexpr double kSpacing = 0.1;
    Eigen::MatrixXd cov(kPoints, kPoints);
    for (int i = 0; i < kPoints; ++i)
        for (int j = 0; j < kPoints; ++j)
            cov(i, j) = truth.sill - variogram(truth, std::abs(i - j) * kSpacing);
    const Eigen::LLT<Eigen::MatrixXd> llt(cov);
    EXPECT_EQ(llt.info(), Eigen::Success);
    const Eigen::MatrixXd l = llt.matrixL();
    std::mt19937_64 rng(20261201);
    std::normal_distribution<double> normal;
    EmpiricalSemivariogram mean;
    for (int r = 0; r < realizations; ++r) {
        Eigen::VectorXd u(kPoints);
        for (int i = 0; i < kPoints; ++i)
            u(i) = normal(rng);
        const Eigen::VectorXd z = l * u;
        const auto e =
            empirical_semivariogram(std::vector<double>(z.data(), z.data() + kPoints), kSpacing);
        if (mean.lags.empty()) {
            mean = e;
            for (auto& p : mean.pairs)
                p = 0;
            for (auto& g : mean.gamma)
                g = 0;
        }
        for (std::size_t k = 0; k < e.lags.size(); ++k) {
            mean.gamma[k] += e.gamma[k] / realizations;
            mean.pairs[k] += e.pairs[k];
        }
    }
    return mean;
}

class ModelFit : public ::testing::TestWithParam<VariogramModel> {};

// Nugget within 0.05 (of a 1.1 sill), sill within 10 %, range within 15 %, and the
// best-model choice picks the model the data came from.
TEST_P(ModelFit, RecoversNuggetSillAndRangeAndIsChosen) {
    const VariogramFit truth{GetParam(), 0.1, 1.1, 2.0};
    const auto fits = fit_variograms(synthetic(truth, 300));
    const VariogramFit best = best_fit(fits);
    EXPECT_EQ(best.model, truth.model) << variogram_model_name(best.model);
    const VariogramFit& f = fits[std::size_t(truth.model)];
    EXPECT_NEAR(f.nugget, truth.nugget, 0.05);
    EXPECT_NEAR(f.sill, truth.sill, 0.1 * truth.sill);
    EXPECT_NEAR(f.range, truth.range, 0.15 * truth.range);
}

INSTANTIATE_TEST_SUITE_P(Models, ModelFit,
                         ::testing::Values(VariogramModel::Spherical, VariogramModel::Exponential,
                                           VariogramModel::Gaussian),
                         [](const auto& p) { return std::string(variogram_model_name(p.param)); });

// The signal of a step is the part of gamma the nugget does not explain, as a difference:
// sqrt(2 (gamma(h) - nugget)); the probe pools each side's spread about its own mean.
TEST(Resolution, SignalAndPooledSpreadMatchTheirDefinitionsByHand) {
    const VariogramFit f{VariogramModel::Exponential, 0.2, 1.2, 3.0};
    // gamma(1.5) - nugget = 1 - e^-1.5.
    EXPECT_NEAR(variogram_signal_lm(f, 1.5), std::sqrt(2.0 * (1.0 - std::exp(-1.5))), 1e-12);
    EXPECT_DOUBLE_EQ(variogram_signal_lm(f, 0.0), 0.0);
    // Means 2 and 11; squares (1 + 0 + 1) + (1 + 1) = 4 over 2 + 1 degrees of freedom.
    const ResolutionProbe p = resolution_probe(f, 1.5, {{1.0, 2.0, 3.0}, {10.0, 12.0}});
    EXPECT_EQ(p.differences, 5u);
    EXPECT_EQ(p.ties, 0u);
    EXPECT_NEAR(p.noise_sd_lm, std::sqrt(4.0 / 3.0), 1e-12);
    EXPECT_EQ(p.resolved, p.signal_lm >= 1.6448536269514722 * std::sqrt(4.0 / 3.0));
    EXPECT_FALSE(resolution_probe(f, 1.5, {}).resolved); // no side: nothing to order
    // Phi(z) = 0.95: the stated confidence is the one-sided normal quantile.
    EXPECT_NEAR(0.5 * std::erfc(-kOrderingZ / std::sqrt(2.0)), kOrderingConfidence, 1e-12);
}

// A known noise model: l2 along a parameter whose semivariogram is Gaussian (nugget 0,
// sill 1, range 2), compared on common random numbers whose differences at lag h spread
// with sd(h) = 0.02 sqrt(h) (the rays that change cell grow with h) about side means of
// their own. The step found must order a pair whose true difference is the signal
// correctly 95 % of the time: checked by drawing such pairs, and against the step solved
// by hand from the model.
TEST(Resolution, StepOrdersPairsCorrectlyNinetyFivePercentOfTheTimeUnderAKnownNoiseModel) {
    const VariogramFit f{VariogramModel::Gaussian, 0.0, 1.0, 2.0};
    const auto signal = [](double h) { // by hand: sqrt(2 (1 - exp(-3 (h / 2)^2)))
        return std::sqrt(2.0 * (1.0 - std::exp(-3.0 * (h / 2.0) * (h / 2.0))));
    };
    const auto sd = [](double h) { return 0.02 * std::sqrt(h); };
    std::mt19937_64 rng(20261202);
    std::normal_distribution<double> normal;
    constexpr int kReplicates = 400; // per side: the pooled sd to 2.5 % (798 dof)
    const auto differences = [&](double h) {
        std::vector<std::vector<double>> groups(2);
        for (int r = 0; r < kReplicates; ++r) {
            groups[0].push_back(0.8 * signal(h) + sd(h) * normal(rng));
            groups[1].push_back(-0.3 * signal(h) + sd(h) * normal(rng));
        }
        return groups;
    };
    const Resolution res = resolvable_step(f, differences, 0.05, 2.5);
    ASSERT_TRUE(res.step);
    const double h = *res.step;
    // The model's own answer: signal(h) = z sd(h), bisected here on the formulas above.
    double lo = 1e-9, hi = 0.05;
    for (int i = 0; i < 200; ++i) {
        const double mid = std::sqrt(lo * hi);
        (signal(mid) >= 1.6448536269514722 * sd(mid) ? hi : lo) = mid;
    }
    // The pooled sd is known to 2.5 % (one standard error), so the step (~ sd^2 at small
    // lags, where signal ~ h and sd ~ h^1/2) to ~5 %; 15 % is three standard errors.
    EXPECT_NEAR(h / hi, 1.0, 0.15) << h << " against " << hi;
    // Draw pairs a step apart whose true difference is the signal: the fraction ordered
    // correctly is Phi(signal / sd) = 0.95 up to the step's error (3 standard errors:
    // +-0.015) and the draw's (2e5 pairs: +-0.0015 at three standard errors).
    int correct = 0;
    constexpr int kPairs = 200000;
    for (int i = 0; i < kPairs; ++i)
        correct += signal(h) + sd(h) * normal(rng) > 0.0 ? 1 : 0;
    EXPECT_NEAR(double(correct) / kPairs, 0.95, 0.017);
    // One standard deviation of the fresh-ray difference, the old rule, orders 84 %: the
    // step at 95 % is coarser than where the signal first equals the spread.
    double one_sd = 1e-9, top = 0.05;
    for (int i = 0; i < 200; ++i) {
        const double mid = std::sqrt(one_sd * top);
        (signal(mid) >= sd(mid) ? top : one_sd) = mid;
    }
    EXPECT_GT(h, 2.0 * top);
    // Every probe's verdict is the rule at its lag.
    for (const ResolutionProbe& p : res.probes)
        EXPECT_EQ(p.resolved, p.signal_lm >= kOrderingZ * p.noise_sd_lm) << p.lag;
}

// Differences that come out exactly 0 (no ray changed cell) order nothing: below the lag
// where rays start to move, the step is not resolved however small the spread.
TEST(Resolution, TiedDifferencesAreNotOrders) {
    const VariogramFit f{VariogramModel::Gaussian, 0.0, 1.0, 2.0};
    const double moves = 0.01; // below this lag every difference is 0
    const auto differences = [&](double h) {
        std::vector<std::vector<double>> g(1);
        for (int r = 0; r < 16; ++r)
            g[0].push_back(h < moves ? 0.0 : 1e-9 * (r % 2 ? 1.0 : -1.0) + h);
        return g;
    };
    const Resolution res = resolvable_step(f, differences, 0.05, 2.5);
    ASSERT_TRUE(res.step);
    EXPECT_GE(*res.step, moves * 0.999);
    EXPECT_LT(*res.step, 1.3 * moves); // the resolved end of a bracket under 1.3x
    bool tied = false;
    for (const ResolutionProbe& p : res.probes)
        if (p.lag < moves) tied = tied || (p.ties == 16 && !p.resolved);
    EXPECT_TRUE(tied);
    // Noise that never falls below the signal: no step, and no probe past the largest lag.
    const auto loud = [](double) { return std::vector<std::vector<double>>{{-10.0, 0.0, 10.0}}; };
    const Resolution none = resolvable_step(f, loud, 0.05, 2.5);
    EXPECT_FALSE(none.step);
    for (const ResolutionProbe& p : none.probes)
        EXPECT_LE(p.lag, 2.5);
}

TEST(Semivariogram, CalibratedStepFollowsTheRuleAndRoundsUp) {
    ParameterSemivariogram p{.recommended_step = 0.1234, .resolvable_step = 0.05};
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Range), 0.13); // up to two digits
    EXPECT_DOUBLE_EQ(calibrated_step(p), 0.05); // the default rule: the resolvable step
    p.resolvable_step = 0.3;
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Range), 0.3); // never below the resolvable
    p.resolvable_step = 0.01234;
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Resolvable), 0.013);
    p.resolvable_step.reset(); // never above the noise: no step to write
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Resolvable), 0.0);
}

} // namespace
} // namespace fird::test
