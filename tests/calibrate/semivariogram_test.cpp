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

TEST(Semivariogram, ResolvableStepIsWhereTheSignalDoublesTheNugget) {
    // Exponential: n + c (1 - e^(-3h/a)) = 2n at h = -a/3 ln(1 - n/c).
    const VariogramFit f{VariogramModel::Exponential, 0.2, 1.2, 3.0};
    const auto h = resolvable_step(f);
    ASSERT_TRUE(h);
    EXPECT_NEAR(*h, -3.0 / 3.0 * std::log(1.0 - 0.2 / 1.0), 1e-9);
    EXPECT_FALSE(resolvable_step({VariogramModel::Spherical, 0.5, 0.9, 1.0})); // never
    // A fit with no nugget stands above the measured noise instead: Gaussian with nugget 0,
    // c (1 - e^(-3 (h/a)^2)) = v at h = a sqrt(-ln(1 - v/c) / 3).
    const VariogramFit g{VariogramModel::Gaussian, 0.0, 2.0, 4.0};
    EXPECT_DOUBLE_EQ(*resolvable_step(g), 0.0);
    const auto hg = resolvable_step(g, 0.01);
    ASSERT_TRUE(hg);
    EXPECT_NEAR(*hg, 4.0 * std::sqrt(-std::log(1.0 - 0.01 / 2.0) / 3.0), 1e-9);
    EXPECT_NEAR(*resolvable_step(f, 0.01), *h, 1e-12); // a nugget above the noise rules
    ParameterSemivariogram p{.recommended_step = 0.1234, .resolvable_step = 0.05};
    EXPECT_DOUBLE_EQ(calibrated_step(p), 0.13); // up to two significant digits
    p.resolvable_step = 0.3;
    EXPECT_DOUBLE_EQ(calibrated_step(p), 0.3); // never below the resolvable step
    p.resolvable_step = 0.01234;
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Resolvable), 0.013);
    p.resolvable_step.reset(); // never above the noise: no step to write
    EXPECT_DOUBLE_EQ(calibrated_step(p, StepRule::Resolvable), 0.0);
}

} // namespace
} // namespace fird::test
