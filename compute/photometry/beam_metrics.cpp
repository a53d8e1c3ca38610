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
    std::vector<double> row_cd(f.height, 0.0);
    for (std::uint32_t r = 0; r < f.height; ++r) {
        // Row r spans altitudes from pi/2 - r pi/H down to pi/2 - (r + 1) pi/H.
        const double top = pi / 2 - pi * r / f.height, bottom = pi / 2 - pi * (r + 1) / f.height;
        const double cell_sr = dphi * (std::sin(top) - std::sin(bottom));
        double row_lm = 0.0;
        for (std::uint32_t c = 0; c < f.width; ++c)
            row_lm += f.lm[std::size_t(r) * f.width + c];
        row_cd[r] = row_lm / (cell_sr * f.width);
    }
    const double top_cd = *std::max_element(row_cd.begin(), row_cd.end());
    if (!(top_cd > 0.0)) return m;
    // Patches of about 1 degree of gamma by 5 of C, whole cells of the grid (no cell is
    // assigned to a node, so no half-cell shift), and a cap of whole rows at each pole.
    const auto rows = std::max<std::uint32_t>(1, std::uint32_t(std::lround(f.height / 180.0)));
    const auto cols = std::max<std::uint32_t>(1, std::uint32_t(std::lround(5.0 * f.width / 360.0)));
    for (std::uint32_t r0 = 0; r0 < f.height; r0 += rows) {
        const std::uint32_t r1 = std::min(f.height, r0 + rows);
        const double top = pi / 2 - pi * r0 / f.height, bottom = pi / 2 - pi * r1 / f.height;
        const bool cap = r0 == 0 || r1 == f.height;
        const std::uint32_t step = cap ? f.width : cols;
        for (std::uint32_t c0 = 0; c0 < f.width; c0 += step) {
            const std::uint32_t c1 = std::min(f.width, c0 + step);
            double lm = 0.0;
            for (std::uint32_t r = r0; r < r1; ++r)
                for (std::uint32_t c = c0; c < c1; ++c)
                    lm += f.lm[std::size_t(r) * f.width + c];
            const double sr = dphi * (c1 - c0) * (std::sin(top) - std::sin(bottom));
            m.peak_cd = std::max(m.peak_cd, lm / sr);
        }
    }
    const double half = 0.5 * top_cd;
    std::uint32_t last = 0; // the last row at or above half the maximum
    for (std::uint32_t r = 0; r < f.height; ++r)
        if (row_cd[r] >= half) last = r;
    // Row centres at gamma = (r + 1/2) pi / H from the zenith; the edge between `last` and
    // the row after it, where the average crosses half its maximum.
    const double row_deg = 180.0 / f.height;
    double gamma_deg = (last + 0.5) * row_deg;
    if (last + 1 < f.height) {
        const double a = row_cd[last], b = row_cd[last + 1];
        if (a > b) gamma_deg += row_deg * (a - half) / (a - b);
    }
    m.beam_angle_deg = std::min(360.0, 2.0 * gamma_deg);
    return m;
}

} // namespace fird
