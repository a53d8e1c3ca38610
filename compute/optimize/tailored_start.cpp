#include "tailored_start.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "model/source.hpp"

namespace fird {

namespace {

constexpr double kPi = std::numbers::pi;
// RK4 steps over the source's cone: the flux map is piecewise linear (kinks at the bands'
// edges), where RK4 falls to first order, so the steps are many and cheap (0.02 degree for
// a 90 degree cone; tailoring_test.cpp bounds what is left).
constexpr int kSteps = 4000;
// The rim's angle is bisected to far below a step: 60 halvings of 90 degrees.
constexpr int kRimBisections = 60;
// The curve stays below the source's level: a cone's edge 0.06 degree short of horizontal.
constexpr double kThetaCap = 0.5 * kPi - 1e-3;
// The mirror's normal turned to horizontal: (theta +- gamma) / 2 this near pi / 2 is a
// curve that runs off to infinity (d(ln rho)/d(theta) = tan of it).
constexpr double kBlowUp = 0.5 * kPi - 1e-6;
// A curve whose distance grows past this many apex depths has run off (a blow-up in all
// but name: the profile would be clamped by the holder long before).
constexpr double kMaxGrowth = 1e6;
constexpr int kCurveSamples = 200;

struct Curve {
    bool ran_off = false;
    double ran_off_at = 0.0;        // theta where it did
    std::vector<double> theta, lnr; // nodes
};

} // namespace

PolarCdf polar_cdf(const std::vector<double>& band_lm) {
    PolarCdf c;
    c.cumulative_lm.assign(1, 0.0);
    for (double b : band_lm)
        c.cumulative_lm.push_back(c.cumulative_lm.back() + std::max(b, 0.0));
    return c;
}

double PolarCdf::at(double angle_rad) const {
    const std::size_t bands = cumulative_lm.size() - 1;
    if (bands == 0) return 0.0;
    const double x = std::clamp(angle_rad / kPi * double(bands), 0.0, double(bands));
    const std::size_t k = std::min(std::size_t(x), bands - 1);
    return cumulative_lm[k] + (x - double(k)) * (cumulative_lm[k + 1] - cumulative_lm[k]);
}

double PolarCdf::inverse(double flux_lm) const {
    const std::size_t bands = cumulative_lm.size() - 1;
    if (bands == 0 || !(total_lm() > 0.0)) return 0.0;
    const double width = kPi / double(bands);
    const double f = std::clamp(flux_lm, 0.0, total_lm());
    // The first edge holding more than f (f = 0: the start of the first lit band, so that
    // the map is continuous where it begins).
    const auto e = f > 0.0 ? std::lower_bound(cumulative_lm.begin() + 1, cumulative_lm.end(), f)
                           : std::upper_bound(cumulative_lm.begin() + 1, cumulative_lm.end(), 0.0);
    const std::size_t k = std::size_t(e - cumulative_lm.begin()) - 1; // band k holds it
    const double in_band = cumulative_lm[k + 1] - cumulative_lm[k];
    const double frac = in_band > 0.0 ? (f - cumulative_lm[k]) / in_band : 0.0;
    return (double(k) + std::clamp(frac, 0.0, 1.0)) * width;
}

std::vector<double> source_nadir_bands_lm(const SourceDesc& source, std::uint64_t rays,
                                          std::uint32_t bands) {
    std::vector<double> b(bands, 0.0);
    const double lm_per_ray = source.flux_lm / double(rays);
    for (std::uint64_t i = 0; i < rays; ++i) {
        const Ray ray = emit_ray(source, SamplerKind::Stratified, 1, i, rays);
        const double theta = std::acos(std::clamp(-ray.direction.z, -1.0, 1.0));
        b[std::min<std::size_t>(bands - 1, std::size_t(theta / kPi * bands))] += lm_per_ray;
    }
    return b;
}

std::vector<double> farfield_zenith_bands_lm(const FarField& farfield) {
    std::vector<double> b(farfield.height, 0.0);
    for (std::uint32_t j = 0; j < farfield.height; ++j)
        for (std::uint32_t i = 0; i < farfield.width; ++i)
            b[j] += farfield.lm[std::size_t(j) * farfield.width + i];
    return b;
}

const char* edge_ray_name(EdgeRay edge) {
    return edge == EdgeRay::Diverging ? "diverging" : "crossing";
}

TailoredProfile tailor_profile(const TailoringProblem& p) {
    if (!(p.apex_depth_mm > 0.0))
        throw std::invalid_argument(
            fmt::format("the tailored start needs the apex below the source (apex depth {:g} mm)",
                        p.apex_depth_mm));
    if (!(p.radius_mm > 0.0) || p.heights < 2)
        throw std::invalid_argument("the tailored start needs a profile radius and two heights");
    // The target's light below the horizon (gamma > 90 degrees) is left out of its CDF: a
    // reflector below its source sends light there only off walls steeper than its cone's
    // edge, and mapping onto it makes tan((theta + gamma) / 2) run off (a downlight's file
    // holds 1.4 % there). Within the upper half, theta < 90 degrees keeps (theta +- gamma) / 2
    // inside (-90, 90) degrees: the curve never runs off.
    std::vector<double> upper = p.target_band_lm;
    for (std::size_t k = 0; k < upper.size(); ++k)
        if (double(k) / double(upper.size()) >= 0.5) upper[k] = 0.0;
    const PolarCdf source = polar_cdf(p.source_band_lm), target = polar_cdf(upper);
    const double all_target = polar_cdf(p.target_band_lm).total_lm();
    if (!(target.total_lm() > 0.0))
        throw std::invalid_argument(
            "the tailored start: the desired far field holds no light above the horizon");
    if (!(source.total_lm() > 0.0))
        throw std::invalid_argument("the tailored start: the source emits no light");
    const double sign = p.edge == EdgeRay::Diverging ? 1.0 : -1.0;

    // gamma(theta): the far-field angle holding the share of the target's flux that the
    // cone [0, theta] holds of the source's flux within the rim's cone [0, rim]. The whole
    // target above the horizon is mapped: under the default [trace] direct = "exclude" the
    // far field is reflected light only, so all of it is the reflector's to make (with
    // direct = "include" the source's direct light is not taken out of it).
    const auto gamma_at = [&](double theta, double rim) {
        const double in_rim = source.at(rim);
        const double share = in_rim > 0.0 ? std::min(1.0, source.at(theta) / in_rim) : 0.0;
        return target.inverse(share * target.total_lm());
    };
    // The mirror law in polar form about the source: the curve P = rho u(theta), u =
    // (sin theta, -cos theta) in the meridional (r, z) plane, reflects u into o = (sin beta,
    // cos beta), beta = +-gamma, when its tangent rho' u + rho u' is normal to o - u (the
    // normal bisects -incident and reflected): rho' (u.o - 1) + rho (u'.o) = 0, and with
    // u.o = -cos(theta + beta), u'.o = sin(theta + beta): d(ln rho)/d(theta) =
    // tan((theta + beta) / 2). beta = 0 gives rho = f / cos^2(theta / 2), the parabola with
    // its focus at the source; beta = theta gives rho = d / cos theta, a flat mirror.
    const auto integrate = [&](double rim) {
        Curve c;
        const double h = rim / kSteps;
        const auto slope = [&](double theta, bool& off) {
            const double a = 0.5 * (theta + sign * gamma_at(theta, rim));
            if (std::abs(a) >= kBlowUp) off = true;
            return off ? 0.0 : std::tan(a);
        };
        double lnr = std::log(p.apex_depth_mm);
        const double max_lnr = lnr + std::log(kMaxGrowth);
        c.theta.push_back(0.0);
        c.lnr.push_back(lnr);
        for (int s = 0; s < kSteps; ++s) {
            const double t = s * h;
            bool off = false;
            const double k1 = slope(t, off), k2 = slope(t + 0.5 * h, off),
                         k3 = slope(t + 0.5 * h, off), k4 = slope(t + h, off);
            lnr += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            if (off || !std::isfinite(lnr) || lnr > max_lnr) {
                c.ran_off = true;
                c.ran_off_at = t;
                return c;
            }
            c.theta.push_back(t + h);
            c.lnr.push_back(lnr);
        }
        return c;
    };
    // How far the curve's end lies beyond the rim's radius (+inf: it ran off before).
    const auto past_rim = [&](const Curve& c) {
        return c.ran_off ? HUGE_VAL
                         : std::exp(c.lnr.back()) * std::sin(c.theta.back()) - p.radius_mm;
    };

    // The rim's angle: the cone whose curve ends at the rim's radius (its flux map depends
    // on the cone, so the two are found together), bisected; the curve of the cone within.
    TailoredProfile out;
    double lo = 1e-4, hi = kThetaCap;
    Curve curve = integrate(hi);
    if (past_rim(curve) <= 0.0) {
        out.reaches_rim = false; // it rises to the source's level inside the rim
    } else {
        Curve inner = integrate(lo);
        if (past_rim(inner) > 0.0)
            throw std::invalid_argument(fmt::format(
                "the tailored start: the apex {:g} mm below the source is already wider than "
                "the radius {:g} mm",
                p.apex_depth_mm, p.radius_mm));
        for (int i = 0; i < kRimBisections; ++i) {
            const double mid = 0.5 * (lo + hi);
            Curve c = integrate(mid);
            if (past_rim(c) > 0.0) {
                hi = mid;
            } else {
                lo = mid;
                inner = std::move(c);
            }
        }
        curve = std::move(inner);
    }
    out.rim_polar_rad = curve.theta.back();
    out.target_share_left_out = 1.0 - target.total_lm() / all_target;
    // A cone that holds next to none of the source's light: the curve only reaches the rim
    // by running off (what is left of the source cannot make the target).
    if (out.rim_polar_rad < 1.0 * kPi / 180.0)
        throw std::invalid_argument(fmt::format(
            "the tailored start ({}): the curve reaches the rim within {:.2f} degrees of the "
            "nadir",
            edge_ray_name(p.edge), out.rim_polar_rad * 180.0 / kPi));
    out.source_share = source.at(out.rim_polar_rad) / source.total_lm();

    // The curve as z(r): r must grow with theta (a height field); a crossing design whose
    // rays turn the mirror past vertical folds back and is refused.
    std::vector<double> r, z;
    for (std::size_t i = 0; i < curve.theta.size(); ++i) {
        const double rho = std::exp(curve.lnr[i]);
        r.push_back(rho * std::sin(curve.theta[i]));
        z.push_back(-rho * std::cos(curve.theta[i]));
        if (!std::isfinite(r.back()) || !std::isfinite(z.back()))
            throw std::invalid_argument("the tailored start: the curve is not finite");
        if (i > 0 && !(r[i] > r[i - 1]))
            throw std::invalid_argument(fmt::format(
                "the tailored start ({}): the curve turns back towards the axis at {:.2f} "
                "degrees from the nadir (no height field)",
                edge_ray_name(p.edge), curve.theta[i] * 180.0 / kPi));
    }
    for (int k = 0; k < p.heights; ++k) {
        const double rk = p.radius_mm * k / (p.heights - 1);
        const auto it = std::lower_bound(r.begin(), r.end(), rk);
        if (it == r.end()) {
            out.z_mm.push_back(z.back()); // beyond the curve (it reached the source's level)
        } else if (it == r.begin()) {
            out.z_mm.push_back(z.front());
        } else {
            const std::size_t i = std::size_t(it - r.begin());
            const double t = (rk - r[i - 1]) / (r[i] - r[i - 1]);
            out.z_mm.push_back(z[i - 1] + t * (z[i] - z[i - 1]));
        }
    }
    for (std::size_t i = 0; i < curve.theta.size(); i += curve.theta.size() / kCurveSamples) {
        out.theta_rad.push_back(curve.theta[i]);
        out.gamma_rad.push_back(gamma_at(curve.theta[i], out.rim_polar_rad));
        out.r_mm.push_back(r[i]);
        out.curve_z_mm.push_back(z[i]);
    }
    return out;
}

} // namespace fird
