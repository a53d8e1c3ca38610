#include "surface_distance.hpp"

#include <cmath>

namespace fird {

double surface_rms_distance_mm(const Surface& a, const Surface& b, int n) {
    const Holder& h = a.holder();
    double sum = 0.0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = h.min_mm.x + (i + 0.5) / n * (h.max_mm.x - h.min_mm.x);
            const double y = h.min_mm.y + (j + 0.5) / n * (h.max_mm.y - h.min_mm.y);
            const double d = a.height(x, y) - b.height(x, y);
            sum += d * d;
        }
    return std::sqrt(sum / (double(n) * n));
}

} // namespace fird
