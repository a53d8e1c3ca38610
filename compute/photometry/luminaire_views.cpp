#include "luminaire_views.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

namespace fird {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

double gamma_holding_deg(const CandelaTable& table, double share) {
    // The zonal flux between gamma steps of 0.25 deg (the table's intensity averaged over
    // C at the step's middle, times the zone's solid angle 2 pi (cos a - cos b)).
    constexpr int zones = 720;
    std::array<double, zones> flux{};
    double total = 0.0;
    for (int z = 0; z < zones; ++z) {
        const double a = 180.0 * z / zones, b = 180.0 * (z + 1) / zones, g = 0.5 * (a + b);
        double mean_cd = 0.0;
        constexpr int planes = 72;
        for (int c = 0; c < planes; ++c)
            mean_cd += intensity_cd(table, 360.0 * c / planes, g) / planes;
        flux[std::size_t(z)] =
            mean_cd * 2.0 * std::numbers::pi * (std::cos(a * kDeg) - std::cos(b * kDeg));
        total += flux[std::size_t(z)];
    }
    if (!(total > 0.0)) return 0.0;
    double sum = 0.0;
    for (int z = 0; z < zones; ++z) {
        sum += flux[std::size_t(z)];
        if (sum >= share * total) return 180.0 * (z + 1) / zones;
    }
    return 180.0;
}

std::vector<IsoSegment> isocandela_segments(const CandelaTable& table,
                                            const std::vector<double>& levels_cd,
                                            double gamma_max_deg, double c_step_deg,
                                            double gamma_step_deg) {
    if (!(c_step_deg > 0.0 && c_step_deg <= 360.0) || !(gamma_step_deg > 0.0) ||
        !std::isfinite(gamma_max_deg))
        throw std::invalid_argument(
            fmt::format("isocandela lines: steps {} x {} deg and a gamma range of {} deg",
                        c_step_deg, gamma_step_deg, gamma_max_deg));
    gamma_max_deg = std::clamp(gamma_max_deg, 0.0, 180.0);
    const int nc = std::max(1, int(std::lround(360.0 / c_step_deg)));
    const int ng =
        std::max(1, int(std::ceil(std::clamp(gamma_max_deg, 0.0, 180.0) / gamma_step_deg - 1e-9)));
    const double dc = 360.0 / nc, dg = std::min(gamma_max_deg, 180.0) / ng;
    std::vector<double> v(std::size_t(nc + 1) * (ng + 1));
    for (int j = 0; j <= ng; ++j)
        for (int i = 0; i <= nc; ++i)
            v[std::size_t(j) * (nc + 1) + i] =
                intensity_cd(table, std::fmod(i * dc, 360.0), j * dg);
    std::vector<IsoSegment> out;
    for (const double level : levels_cd)
        for (int j = 0; j < ng; ++j)
            for (int i = 0; i < nc; ++i) {
                // Corners counter-clockwise from (i, j): their values and places.
                const std::array<double, 4> x{double(i), double(i + 1), double(i + 1), double(i)};
                const std::array<double, 4> y{double(j), double(j), double(j + 1), double(j + 1)};
                std::array<double, 4> f;
                for (int k = 0; k < 4; ++k)
                    f[std::size_t(k)] = v[std::size_t(y[std::size_t(k)]) * (nc + 1) +
                                          std::size_t(x[std::size_t(k)])] -
                                        level;
                // The crossings on the cell's edges (k to k + 1), linear between corners.
                std::vector<std::array<double, 2>> cuts;
                for (std::size_t k = 0; k < 4; ++k) {
                    const std::size_t n = (k + 1) % 4;
                    if ((f[k] < 0.0) == (f[n] < 0.0)) continue;
                    const double t = f[k] / (f[k] - f[n]);
                    cuts.push_back({x[k] + t * (x[n] - x[k]), y[k] + t * (y[n] - y[k])});
                }
                const auto emit = [&](const std::array<double, 2>& a,
                                      const std::array<double, 2>& b) {
                    out.push_back({level, a[0] * dc, a[1] * dg, b[0] * dc, b[1] * dg});
                };
                if (cuts.size() == 2) emit(cuts[0], cuts[1]);
                if (cuts.size() == 4) {
                    // A saddle (edges 0 bottom, 1 right, 2 top, 3 left): the mean of the
                    // corners stands for the centre. On corner 0's side, it joins corners 0
                    // and 2, and the lines cut off corners 1 and 3; else corners 0 and 2.
                    const double mean = 0.25 * (f[0] + f[1] + f[2] + f[3]);
                    if ((mean < 0.0) == (f[0] < 0.0))
                        emit(cuts[0], cuts[1]), emit(cuts[2], cuts[3]);
                    else
                        emit(cuts[3], cuts[0]), emit(cuts[1], cuts[2]);
                }
            }
    return out;
}

IlluminanceMap illuminance_on_plane(const CandelaTable& table, double distance_m,
                                    double half_width_m, int samples) {
    if (!(distance_m > 0.0) || !std::isfinite(distance_m) || !(half_width_m >= 0.0) ||
        !std::isfinite(half_width_m))
        throw std::invalid_argument(fmt::format("illuminance: a plane {} m away, {} m either side",
                                                distance_m, half_width_m));
    IlluminanceMap m{
        .samples = std::max(samples, 1), .distance_m = distance_m, .half_width_m = half_width_m};
    m.lux.resize(std::size_t(m.samples) * m.samples);
    for (int iy = 0; iy < m.samples; ++iy)
        for (int ix = 0; ix < m.samples; ++ix)
            m.lux[std::size_t(iy) * m.samples + ix] =
                illuminance_at(table, distance_m, m.position_m(ix), m.position_m(iy)).lux;
    return m;
}

PlanePoint illuminance_at(const CandelaTable& table, double distance_m, double x_m, double y_m) {
    const double r = std::hypot(x_m, y_m);
    const double gamma = std::atan2(r, distance_m);
    double c = r > 0.0 ? std::atan2(y_m, x_m) / kDeg : 0.0;
    if (c < 0.0) c += 360.0;
    const double cos_g = std::cos(gamma);
    return {intensity_cd(table, c, gamma / kDeg) * cos_g * cos_g * cos_g /
                (distance_m * distance_m),
            c, gamma / kDeg};
}

} // namespace fird
