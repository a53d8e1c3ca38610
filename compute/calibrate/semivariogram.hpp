// The semivariogram of a regularly spaced series (the paper's §5.1, Figure 8): Matheron's
// estimator, and spherical, exponential and Gaussian models with a nugget fitted by
// Cressie's weighted least squares, from which the smallest useful optimization step.
#pragma once

#include <cstddef>
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

// The smallest lag whose expected difference stands above the noise: where
// gamma(h) - nugget first exceeds the noise, the larger of the nugget and the measured
// variance of l2 at one reflector (nullopt when it never does).
std::optional<double> resolvable_step(const VariogramFit& fit, double noise_variance = 0.0);

} // namespace fird
