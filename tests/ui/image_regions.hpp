// Comparing regions of two screenshots of the same size (the windowed and offscreen
// sessions' checks).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <vector>

namespace fird::test {

// Mean absolute channel difference over a region given as fractions of the window.
inline double region_difference(const std::vector<std::uint8_t>& a,
                                const std::vector<std::uint8_t>& b, int w, int h, double x0,
                                double y0, double x1, double y1) {
    double sum = 0.0;
    std::size_t n = 0;
    for (int y = int(y0 * h); y < int(y1 * h); ++y)
        for (int x = int(x0 * w); x < int(x1 * w); ++x)
            for (int k = 0; k < 3; ++k, ++n) {
                const std::size_t i = (std::size_t(y) * w + x) * 4 + k;
                sum += std::abs(int(a[i]) - int(b[i]));
            }
    return n ? sum / double(n) : 0.0;
}

} // namespace fird::test
