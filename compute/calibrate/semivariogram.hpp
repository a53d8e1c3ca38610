// The semivariogram of a regularly spaced series (the paper's §5.1, Figure 8): Matheron's
// estimator, and spherical, exponential and Gaussian models with a nugget fitted by
// Cressie's weighted least squares, from which the smallest useful optimization step.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace fird {

struct EmpiricalSemivariogram {
    std::vector<double> lags;  // multiples of the spacing, up to half the span
    std::vector<double> gamma; // gamma(h) = 1 / (2 n(h)) sum (Z(x + h) - Z(x))^2
    std::vector<std::size_t> pairs;
};

// Z at x_i = x_0 + i * spacing, i = 0 .. K-1 (K >= 3); a NaN Z (not measured) takes
// no part in any pair, and a lag without pairs is left out.
EmpiricalSemivariogram empirical_semivariogram(const std::vector<double>& z, double spacing);

enum class VariogramModel { Spherical, Exponential, Gaussian };
const char* variogram_model_name(VariogramModel m);

struct VariogramFit {
    VariogramModel model = VariogramModel::Spherical;
    double nugget = 0.0; // gamma just above 0: the noise between two measurements
    double sill = 0.0;   // nugget + partial sill: gamma at long lags
    // Spherical: where gamma reaches the sill; exponential and Gaussian: the practical
    // range, where gamma reaches 95 % of the partial sill above the nugget.
    double range = 0.0;
    double residual = 0.0; // Cressie's weighted residual sum n(h) (gamma^ / gamma - 1)^2
};

// The model's gamma at lag h.
double variogram(const VariogramFit& fit, double h);

// Each model fitted (nugget, partial sill >= 0; range within (0, 4 * the largest lag]).
std::vector<VariogramFit> fit_variograms(const EmpiricalSemivariogram& e);
// The fit with the smallest weighted residual.
VariogramFit best_fit(const std::vector<VariogramFit>& fits);

// The resolvable step: the smallest step at which a search orders two points a step apart
// correctly with kOrderingConfidence, judged on the differences it actually compares.
//
// A search traces the candidates of one stage with the same rays (common random numbers,
// Evaluator), so what it compares is D(h) = l2(x + h; w) - l2(x; w) on one rayset w. D's
// mean is the signal: between two points of the series a step h apart its mean square is
// 2 (gamma(h) - nugget) (the series is traced with fresh rays per point, so the fitted
// nugget is the fresh-ray noise, and what rises above it is the l2 surface itself). D's
// spread about that mean is the noise of the comparison: with the same rays it is below
// the fresh-ray difference's (2 sigma^2), and falls toward 0 as h -> 0, where both traces
// send more and more rays to the same cell; neither the nugget nor sigma, it must be
// measured: sd(h), from replicate raysets. With D ~ Normal(signal, sd^2) the pair is
// ordered correctly (D has the sign of its mean) with probability Phi(signal / sd), so the
// step is resolved at the confidence c where signal(h) >= z_c sd(h), z_c = Phi^-1(c) (1.645
// for 95 %: not one standard deviation, which orders a pair correctly 84 % of the time). A
// difference that comes out exactly 0 (no ray changed cell) orders nothing: a lag where
// more than 1 - c of them do is not resolved, whatever the spread.
constexpr double kOrderingConfidence = 0.95;
constexpr double kOrderingZ = 1.6448536269514722; // Phi^-1(0.95)

// Common-random-number differences at lag h: one group per side of the point (x + h and
// x - h), each difference l2(x +- h; w_r) - l2(x; w_r) for one replicate rayset w_r. Each
// group's own mean is removed (the two sides' signals differ), their spreads pooled.
using CommonRandomDifferences = std::function<std::vector<std::vector<double>>(double lag)>;

struct ResolutionProbe {
    double lag = 0.0;
    double signal_lm = 0.0;   // sqrt(2 (gamma(lag) - nugget))
    double noise_sd_lm = 0.0; // pooled sample sd of the differences (NaN: fewer than 2)
    std::size_t differences = 0;
    std::size_t ties = 0; // differences exactly 0
    bool resolved = false;
};

struct Resolution {
    std::optional<double> step;          // nullopt: not resolved up to the largest lag
    std::vector<ResolutionProbe> probes; // in the order they were measured
};

// The signal of the fitted model at lag h: the RMS difference of l2 between two points a
// step h apart that noise does not explain, sqrt(2 (gamma(h) - nugget)).
double variogram_signal_lm(const VariogramFit& fit, double h);

// Pools the groups' spreads and decides one lag (no side at all: not resolved).
ResolutionProbe resolution_probe(const VariogramFit& fit, double lag,
                                 const std::vector<std::vector<double>>& groups);

// Finds the resolvable step by probing lags: from first_lag down by factors of 4 while
// resolved (or up by 2 while not, up to max_lag), then narrowing the bracket [failed,
// resolved] by interpolating log(signal / (z sd)) linearly in log h (the signal ~ h and
// sd grows more slowly at small lags: near a straight line there) until it spans under
// 1.3x. The step is the interpolated lag where signal = z sd (where an end decided on ties,
// the finest resolved lag). A floor of first_lag / 4^8 bounds the descent.
Resolution resolvable_step(const VariogramFit& fit, const CommonRandomDifferences& differences,
                           double first_lag, double max_lag);

} // namespace fird
