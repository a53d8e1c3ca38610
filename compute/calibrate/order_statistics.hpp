// Quantiles of a sample: linear between its order statistics (q = 0.5 the median, 0.05 and
// 0.95 a 90 % spread). One definition for the tolerance analysis' spreads and the search
// progress chart's generation bands.
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

namespace fird {

// The q-quantile of `sorted` (ascending), 0 for an empty sample.
inline double sorted_quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    const double at = q * double(sorted.size() - 1);
    const auto i = std::size_t(std::floor(at));
    const double f = at - double(i);
    return i + 1 < sorted.size() ? sorted[i] * (1.0 - f) + sorted[i + 1] * f : sorted[i];
}

} // namespace fird
