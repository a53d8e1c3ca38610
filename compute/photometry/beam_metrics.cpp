#include "beam_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

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

} // namespace fird
