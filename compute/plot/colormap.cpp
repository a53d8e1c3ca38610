#include "colormap.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fird::plot {

namespace {
Rgb lerp_stops(const std::vector<std::array<double, 4>>& stops, double t) {
    t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
    for (std::size_t i = 1; i < stops.size(); ++i)
        if (t <= stops[i][0]) {
            const auto& a = stops[i - 1];
            const auto& b = stops[i];
            const double f = (t - a[0]) / (b[0] - a[0]);
            Rgb c;
            for (int k = 0; k < 3; ++k)
                c[k] = std::uint8_t(std::lround(255.0 * (a[k + 1] + f * (b[k + 1] - a[k + 1]))));
            return c;
        }
    return {255, 255, 255};
}
} // namespace

Rgb sequential_colour(double t) {
    static const std::vector<std::array<double, 4>> stops = {
        {0.0, 0.0, 0.0, 0.0},     {0.25, 0.30, 0.05, 0.45}, {0.5, 0.75, 0.15, 0.35},
        {0.75, 0.98, 0.55, 0.05}, {0.92, 1.0, 0.92, 0.35},  {1.0, 1.0, 1.0, 1.0}};
    return lerp_stops(stops, t);
}

Rgb diverging_colour(double t) {
    static const std::vector<std::array<double, 4>> stops = {
        {0.0, 0.10, 0.25, 0.75}, {0.5, 1.0, 1.0, 1.0}, {1.0, 0.75, 0.10, 0.10}};
    return lerp_stops(stops, 0.5 * (std::clamp(t, -1.0, 1.0) + 1.0));
}

} // namespace fird::plot
