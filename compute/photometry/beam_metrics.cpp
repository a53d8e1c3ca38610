#include "beam_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

namespace fird {

BeamMetrics beam_metrics(const FarField& f) {
    BeamMetrics m;
    const double pi = std::numbers::pi;
    const double dphi = 2.0 * pi / f.width;
    // Bands of about 1 degree of gamma (whole rows): the beam's profile, and the peak's
    // patches within them. A single row about the zenith is too small to average (a 0.2
    // degree row holds tens of rays at 2e5).
    const auto rows = std::max<std::uint32_t>(1, std::uint32_t(std::lround(f.height / 180.0)));
    const auto cols = std::max<std::uint32_t>(1, std::uint32_t(std::lround(5.0 * f.width / 360.0)));
    std::vector<double> band_cd, band_end_deg;
    for (std::uint32_t r0 = 0; r0 < f.height; r0 += rows) {
        const std::uint32_t r1 = std::min(f.height, r0 + rows);
        const double top = pi / 2 - pi * r0 / f.height, bottom = pi / 2 - pi * r1 / f.height;
        const double band_sr = 2.0 * pi * (std::sin(top) - std::sin(bottom));
        // Patches of about 5 degrees of C; a cap of whole rows at each pole.
        const bool cap = r0 == 0 || r1 == f.height;
        const std::uint32_t step = cap ? f.width : cols;
        double band_lm = 0.0;
        for (std::uint32_t c0 = 0; c0 < f.width; c0 += step) {
            const std::uint32_t c1 = std::min(f.width, c0 + step);
            double lm = 0.0;
            for (std::uint32_t r = r0; r < r1; ++r)
                for (std::uint32_t c = c0; c < c1; ++c)
                    lm += f.lm[std::size_t(r) * f.width + c];
            band_lm += lm;
            const double sr = dphi * (c1 - c0) * (std::sin(top) - std::sin(bottom));
            m.peak_cd = std::max(m.peak_cd, lm / sr);
        }
        band_cd.push_back(band_lm / band_sr);
        band_end_deg.push_back(180.0 * r1 / f.height);
    }
    const double top_cd = *std::max_element(band_cd.begin(), band_cd.end());
    if (!(top_cd > 0.0)) return m;
    const double half = 0.5 * top_cd;
    std::size_t last = 0; // the last band at or above half the maximum
    for (std::size_t b = 0; b < band_cd.size(); ++b)
        if (band_cd[b] >= half) last = b;
    // Band centres; the edge between `last` and the band after it, where the average
    // crosses half its maximum (linear between the centres).
    const auto centre = [&](std::size_t b) {
        return b == 0 ? 0.5 * band_end_deg[0] : 0.5 * (band_end_deg[b - 1] + band_end_deg[b]);
    };
    double gamma_deg = centre(last);
    if (last + 1 < band_cd.size()) {
        const double a = band_cd[last], b = band_cd[last + 1];
        if (a > b) gamma_deg += (centre(last + 1) - centre(last)) * (a - half) / (a - b);
    }
    m.beam_angle_deg = std::min(360.0, 2.0 * gamma_deg);
    return m;
}

namespace {

// The patches of beam_metrics: bands of about 1 degree of gamma (whole rows), each cut into
// about 5 degrees of C (whole columns), the bands at the poles whole caps.
struct Patches {
    const FarField& f;
    std::uint32_t rows, cols;
    explicit Patches(const FarField& farfield)
        : f(farfield),
          rows(std::max<std::uint32_t>(1, std::uint32_t(std::lround(f.height / 180.0)))),
          cols(std::max<std::uint32_t>(1, std::uint32_t(std::lround(5.0 * f.width / 360.0)))) {}
    bool cap(std::uint32_t r0) const { return r0 == 0 || r0 + rows >= f.height; }
    // Candela of the band from row r0 over `count` columns from c0 (wrapping).
    double cd(std::uint32_t r0, std::uint32_t c0, std::uint32_t count) const {
        const double pi = std::numbers::pi;
        const std::uint32_t r1 = std::min(f.height, r0 + rows);
        const double top = pi / 2 - pi * r0 / f.height, bottom = pi / 2 - pi * r1 / f.height;
        double lm = 0.0;
        for (std::uint32_t r = r0; r < r1; ++r)
            for (std::uint32_t k = 0; k < count; ++k)
                lm += f.lm[std::size_t(r) * f.width + (c0 + k) % f.width];
        const double sr = 2.0 * pi / f.width * count * (std::sin(top) - std::sin(bottom));
        return lm / sr;
    }
    double gamma_centre_deg(std::uint32_t r0) const {
        return 90.0 * (2.0 * r0 + (std::min(f.height, r0 + rows) - r0)) / f.height;
    }
    // The patch about the half-plane C (degrees): C = -phi, column of phi from -pi.
    double half_plane_cd(std::uint32_t r0, double c_deg) const {
        if (cap(r0)) return cd(r0, 0, f.width);
        const double phi_turns = std::fmod(0.5 - c_deg / 360.0 + 2.0, 1.0);
        const auto centre = std::int64_t(std::floor(phi_turns * f.width));
        const auto first = (centre - std::int64_t(cols / 2) + std::int64_t(f.width)) % f.width;
        return cd(r0, std::uint32_t(first), cols);
    }
};

// The angle between the outermost crossings of `share` of the profile's largest value along
// a plane's profile (signed gamma: the second half-plane's negative), linear between
// samples; 0 for a plane without light.
double spread_at(const std::vector<std::pair<double, double>>& profile, double share) {
    double top = 0.0;
    for (const auto& sample : profile)
        top = std::max(top, sample.second);
    if (!(top > 0.0)) return 0.0;
    const double level = share * top;
    std::size_t first = profile.size(), last = 0;
    for (std::size_t k = 0; k < profile.size(); ++k)
        if (profile[k].second >= level) {
            first = std::min(first, k);
            last = k;
        }
    if (first == profile.size()) return 0.0;
    const auto cross = [&](std::size_t in, std::size_t out) {
        const auto [s_in, v_in] = profile[in];
        const auto [s_out, v_out] = profile[out];
        return s_in + (s_out - s_in) * (v_in - level) / (v_in - v_out);
    };
    const double left = first > 0 ? cross(first, first - 1) : profile[first].first;
    const double right = last + 1 < profile.size() ? cross(last, last + 1) : profile[last].first;
    return right - left;
}

} // namespace

Photometrics photometrics(const FarField& f, double source_flux_lm) {
    Photometrics p;
    p.efficiency = source_flux_lm > 0.0 ? f.total_lm() / source_flux_lm : 0.0;
    if (f.width == 0 || f.height == 0) return p;
    const Patches patches(f);
    for (std::uint32_t r0 = 0; r0 < f.height; r0 += patches.rows) {
        const std::uint32_t step = patches.cap(r0) ? f.width : patches.cols;
        for (std::uint32_t c0 = 0; c0 < f.width; c0 += step) {
            const std::uint32_t count = std::min(step, f.width - c0);
            const double cd = patches.cd(r0, c0, count);
            if (cd <= p.peak_cd) continue;
            p.peak_cd = cd;
            // A cap is a ring about its pole: its direction is the pole's.
            p.peak_gamma_deg = !patches.cap(r0) ? patches.gamma_centre_deg(r0)
                               : r0 == 0        ? 0.0
                                                : 180.0;
            const double phi_deg = -180.0 + 360.0 * (c0 + 0.5 * count) / f.width;
            p.peak_c_deg = patches.cap(r0) ? 0.0 : std::fmod(360.0 - phi_deg, 360.0);
        }
    }
    if (!(p.peak_cd > 0.0)) return p;
    // Each plane's profile, from gamma 180 on its second half-plane through the axis to
    // gamma 180 on its first (C0: from C180 to C0).
    const auto profile = [&](double c_deg) {
        std::vector<std::pair<double, double>> out;
        for (std::uint32_t r0 = f.height; r0-- > 0;)
            if (r0 % patches.rows == 0)
                out.emplace_back(-patches.gamma_centre_deg(r0),
                                 patches.half_plane_cd(r0, c_deg + 180.0));
        for (std::uint32_t r0 = 0; r0 < f.height; r0 += patches.rows)
            out.emplace_back(patches.gamma_centre_deg(r0), patches.half_plane_cd(r0, c_deg));
        return out;
    };
    const auto c0 = profile(0.0), c90 = profile(90.0);
    p.beam_angle_deg = {spread_at(c0, 0.5), spread_at(c90, 0.5)};
    p.field_angle_deg = {spread_at(c0, 0.1), spread_at(c90, 0.1)};
    return p;
}

nlohmann::json photometrics_json(const Photometrics& p) {
    return {
        {"efficiency", p.efficiency},
        {"peak_cd", p.peak_cd},
        {"peak_direction_deg", {p.peak_c_deg, p.peak_gamma_deg}},
        {"beam_angle_deg", {{"C0", p.beam_angle_deg.c0_deg}, {"C90", p.beam_angle_deg.c90_deg}}},
        {"field_angle_deg",
         {{"C0", p.field_angle_deg.c0_deg}, {"C90", p.field_angle_deg.c90_deg}}}};
}

std::string photometrics_text(const nlohmann::json& p) {
    const auto angles = [&](const char* key) {
        return fmt::format("{:.1f}/{:.1f}", p[key]["C0"].get<double>(),
                           p[key]["C90"].get<double>());
    };
    return fmt::format("efficiency {:.3f}, peak {:.4g} cd at C {:.1f} gamma {:.1f} deg, beam "
                       "angle C0/C90 {} deg, field angle {} deg",
                       p["efficiency"].get<double>(), p["peak_cd"].get<double>(),
                       p["peak_direction_deg"][0].get<double>(),
                       p["peak_direction_deg"][1].get<double>(), angles("beam_angle_deg"),
                       angles("field_angle_deg"));
}

} // namespace fird
