#include "semivariogram.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <nlopt.hpp>

namespace fird {

EmpiricalSemivariogram empirical_semivariogram(const std::vector<double>& z, double spacing) {
    if (z.size() < 3) throw std::invalid_argument("a semivariogram needs at least 3 points");
    EmpiricalSemivariogram e;
    const std::size_t max_lag = (z.size() - 1) / 2; // half the span
    for (std::size_t k = 1; k <= std::max<std::size_t>(1, max_lag); ++k) {
        double sum = 0.0;
        std::size_t n = 0;
        for (std::size_t i = 0; i + k < z.size(); ++i) {
            const double d = z[i + k] - z[i];
            if (!std::isfinite(d)) continue; // a point not measured (an infeasible value)
            sum += d * d;
            ++n;
        }
        if (n == 0) continue;
        e.lags.push_back(double(k) * spacing);
        e.gamma.push_back(sum / (2.0 * double(n)));
        e.pairs.push_back(n);
    }
    return e;
}

const char* variogram_model_name(VariogramModel m) {
    switch (m) {
    case VariogramModel::Spherical:
        return "spherical";
    case VariogramModel::Exponential:
        return "exponential";
    case VariogramModel::Gaussian:
        return "gaussian";
    }
    return "?";
}

double variogram(const VariogramFit& f, double h) {
    if (h <= 0.0) return 0.0;
    const double c = f.sill - f.nugget;
    const double r = std::max(f.range, 1e-300);
    switch (f.model) {
    case VariogramModel::Spherical:
        return h >= r ? f.sill : f.nugget + c * (1.5 * h / r - 0.5 * std::pow(h / r, 3));
    case VariogramModel::Exponential: // practical range: 1 - e^-3 = 95 %
        return f.nugget + c * (1.0 - std::exp(-3.0 * h / r));
    case VariogramModel::Gaussian:
        return f.nugget + c * (1.0 - std::exp(-3.0 * (h / r) * (h / r)));
    }
    return 0.0;
}

namespace {

struct FitData {
    const EmpiricalSemivariogram* e;
    VariogramModel model;
};

// Cressie (1985): sum n(h) (gamma^(h) / gamma(h; theta) - 1)^2, the weights n(h) /
// gamma(h; theta)^2 of gstat's fit.method 2. theta = (nugget, partial sill, range).
double cressie(unsigned, const double* t, double*, void* data) {
    const auto& d = *static_cast<const FitData*>(data);
    const VariogramFit f{d.model, t[0], t[0] + t[1], t[2]};
    double s = 0.0;
    for (std::size_t k = 0; k < d.e->lags.size(); ++k) {
        const double g = variogram(f, d.e->lags[k]);
        if (!(g > 0.0)) return 1e300;
        const double r = d.e->gamma[k] / g - 1.0;
        s += double(d.e->pairs[k]) * r * r;
    }
    return s;
}

VariogramFit fit_one(const EmpiricalSemivariogram& e, VariogramModel model) {
    const double top = *std::max_element(e.gamma.begin(), e.gamma.end());
    const double scale = top > 0.0 ? top : 1.0;
    const double max_lag = e.lags.back();
    FitData data{&e, model};
    VariogramFit best{model, 0, 0, 0, std::numeric_limits<double>::infinity()};
    // Bounded BOBYQA from a few starts (the residual has local minima in the range).
    for (double r0 : {0.15, 0.4, 0.9})
        for (double n0 : {0.02, 0.3}) {
            nlopt::opt opt(nlopt::LN_BOBYQA, 3);
            opt.set_lower_bounds({0.0, 0.0, 1e-3 * max_lag});
            opt.set_upper_bounds({2.0 * scale, 4.0 * scale, 4.0 * max_lag});
            opt.set_min_objective(cressie, &data);
            opt.set_xtol_rel(1e-8);
            opt.set_maxeval(4000);
            std::vector<double> t{n0 * e.gamma.front(), std::max(1e-6 * scale, scale * (1 - n0)),
                                  r0 * max_lag};
            double value = 0.0;
            try {
                (void)opt.optimize(t, value);
            } catch (const std::exception&) {
                value = cressie(3, t.data(), nullptr, &data);
            }
            if (value < best.residual) best = {model, t[0], t[0] + t[1], t[2], value};
        }
    return best;
}

} // namespace

std::vector<VariogramFit> fit_variograms(const EmpiricalSemivariogram& e) {
    if (e.lags.empty()) throw std::invalid_argument("no lags to fit");
    return {fit_one(e, VariogramModel::Spherical), fit_one(e, VariogramModel::Exponential),
            fit_one(e, VariogramModel::Gaussian)};
}

VariogramFit best_fit(const std::vector<VariogramFit>& fits) {
    return *std::min_element(fits.begin(), fits.end(),
                             [](const auto& a, const auto& b) { return a.residual < b.residual; });
}

double variogram_signal_lm(const VariogramFit& f, double h) {
    return std::sqrt(2.0 * std::max(0.0, variogram(f, h) - f.nugget));
}

ResolutionProbe resolution_probe(const VariogramFit& f, double lag,
                                 const std::vector<std::vector<double>>& groups) {
    ResolutionProbe p{.lag = lag, .signal_lm = variogram_signal_lm(f, lag)};
    double squares = 0.0;
    std::size_t dof = 0;
    for (const std::vector<double>& g : groups) {
        if (g.empty()) continue;
        double mean = 0.0;
        for (double d : g)
            mean += d / double(g.size());
        for (double d : g) {
            squares += (d - mean) * (d - mean);
            p.ties += d == 0.0 ? 1 : 0;
        }
        p.differences += g.size();
        dof += g.size() - 1;
    }
    p.noise_sd_lm = dof > 0 ? std::sqrt(squares / double(dof)) : std::nan("");
    const bool few_ties = double(p.ties) <= (1.0 - kOrderingConfidence) * double(p.differences);
    p.resolved =
        dof > 0 && few_ties && p.signal_lm > 0.0 && p.signal_lm >= kOrderingZ * p.noise_sd_lm;
    return p;
}

namespace {

// log(signal / (z sd)): 0 where the step is just resolved; NaN where a probe decided on
// ties or had no spread to compare.
double log_margin(const ResolutionProbe& p) {
    if (!(p.signal_lm > 0.0) || !(p.noise_sd_lm > 0.0)) return std::nan("");
    return std::log(p.signal_lm / (kOrderingZ * p.noise_sd_lm));
}

} // namespace

Resolution resolvable_step(const VariogramFit& f, const CommonRandomDifferences& differences,
                           double first_lag, double max_lag) {
    Resolution r;
    const auto probe = [&](double lag) -> const ResolutionProbe& {
        r.probes.push_back(resolution_probe(f, lag, differences(lag)));
        return r.probes.back();
    };
    if (!(first_lag > 0.0)) return r;
    std::optional<ResolutionProbe> failed, resolved;
    if (probe(first_lag).resolved) {
        resolved = r.probes.back();
        const double floor = first_lag / 65536.0; // 4^8
        for (double lag = first_lag / 4.0; lag >= floor; lag /= 4.0) {
            const ResolutionProbe& p = probe(lag);
            (p.resolved ? resolved : failed) = p;
            if (!p.resolved) break;
        }
        if (!failed) { // resolved down to the floor: at most that fine
            r.step = resolved->lag;
            return r;
        }
    } else {
        failed = r.probes.back();
        for (double lag = 2.0 * first_lag; lag <= max_lag; lag *= 2.0) {
            const ResolutionProbe& p = probe(lag);
            (p.resolved ? resolved : failed) = p;
            if (p.resolved) break;
        }
        if (!resolved) return r;
    }
    // Narrow the bracket where the margin is a line in log h; bisect (geometrically) where
    // an end has no margin to interpolate (it decided on ties).
    const auto interpolated = [&]() -> std::optional<double> {
        const double a = log_margin(*failed), b = log_margin(*resolved);
        if (!std::isfinite(a) || !std::isfinite(b) || !(b > a)) return std::nullopt;
        const double la = std::log(failed->lag), lb = std::log(resolved->lag);
        return la + (lb - la) * (-a) / (b - a);
    };
    for (int i = 0; i < 4 && resolved->lag > 1.3 * failed->lag; ++i) {
        // Inside the bracket, away from its ends (a lopsided interpolation narrows slowly).
        const double la = std::log(failed->lag), lb = std::log(resolved->lag);
        const double x = std::clamp(interpolated().value_or(0.5 * (la + lb)), la + 0.1 * (lb - la),
                                    lb - 0.1 * (lb - la));
        const ResolutionProbe& p = probe(std::exp(x));
        (p.resolved ? resolved : failed) = p;
    }
    // Without a line to interpolate, the finest lag measured to be resolved.
    const std::optional<double> root = interpolated();
    r.step = root ? std::exp(*root) : resolved->lag;
    return r;
}

} // namespace fird
