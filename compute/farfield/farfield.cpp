#include "farfield.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fird {

double FarField::total_lm() const {
    double s = 0.0;
    for (double v : lm)
        s += v;
    return s;
}

std::uint32_t farfield_cell(const glm::dvec3& d, std::uint32_t width, std::uint32_t height) {
    constexpr double pi = std::numbers::pi;
    // Straight up or down the azimuth is undefined: such a ray takes the column of
    // phi = 0, on both backends (atan2 of signed zeros would give +-pi, i.e. either edge).
    const double phi = (d.x == 0.0 && d.y == 0.0) ? 0.0 : std::atan2(d.y, d.x);
    const double theta = std::asin(std::clamp(d.z, -1.0, 1.0));
    const auto col = std::clamp<std::int64_t>(
        std::int64_t(std::floor((phi + pi) / (2.0 * pi) * width)), 0, width - 1);
    const auto row = std::clamp<std::int64_t>(
        std::int64_t(std::floor((pi / 2.0 - theta) / pi * height)), 0, height - 1);
    return std::uint32_t(row * width + col);
}

FarField farfield_from_counts(const std::vector<std::uint64_t>& counts, std::uint32_t width,
                              std::uint32_t height, double lm_per_ray) {
    FarField f{width, height, std::vector<double>(counts.size())};
    for (std::size_t i = 0; i < counts.size(); ++i)
        f.lm[i] = double(counts[i]) * lm_per_ray;
    return f;
}

double l2_distance(const FarField& a, const FarField& b) {
    return farfield_distance(a, b, FarFieldMetric::L2);
}

const char* metric_name(FarFieldMetric metric) {
    return metric == FarFieldMetric::CandelaL2 ? "candela_l2" : "l2";
}

const char* metric_unit(FarFieldMetric metric) {
    return metric == FarFieldMetric::CandelaL2 ? "cd" : "lm";
}

double metric_cell_weight(FarFieldMetric metric, std::uint32_t row, std::uint32_t width,
                          std::uint32_t height) {
    if (metric == FarFieldMetric::L2) return 1.0;
    return 1.0 / (4.0 * std::numbers::pi * farfield_cell_solid_angle_sr(row, width, height));
}

double farfield_distance(const FarField& a, const FarField& b, FarFieldMetric metric) {
    if (a.width != b.width || a.height != b.height || a.lm.size() != b.lm.size())
        throw std::invalid_argument("far fields of different grids cannot be compared");
    double s = 0.0;
    if (metric == FarFieldMetric::L2) {
        for (std::size_t i = 0; i < a.lm.size(); ++i) {
            const double d = a.lm[i] - b.lm[i];
            s += d * d;
        }
        return std::sqrt(s);
    }
    for (std::uint32_t row = 0; row < a.height; ++row) {
        double row_sum = 0.0;
        for (std::size_t i = std::size_t(row) * a.width; i < std::size_t(row + 1) * a.width; ++i) {
            const double d = a.lm[i] - b.lm[i];
            row_sum += d * d;
        }
        s += row_sum * metric_cell_weight(metric, row, a.width, a.height);
    }
    return std::sqrt(s);
}

double multinomial_noise_lm2_times_rays(const FarField& expected, double flux_lm,
                                        FarFieldMetric metric) {
    double sum = 0.0;
    for (std::uint32_t row = 0; row < expected.height; ++row) {
        double row_sum = 0.0;
        for (std::uint32_t col = 0; col < expected.width; ++col) {
            const double p = expected.lm[std::size_t(row) * expected.width + col] / flux_lm;
            row_sum += p * (1.0 - p);
        }
        sum += row_sum * metric_cell_weight(metric, row, expected.width, expected.height);
    }
    return flux_lm * flux_lm * sum;
}

FarField coarsen_farfield(const FarField& f, std::uint32_t width, std::uint32_t height) {
    if (width == 0 || height == 0 || f.width % width != 0 || f.height % height != 0)
        throw std::invalid_argument("a coarser far-field grid must divide the finer one");
    const std::uint32_t kx = f.width / width, ky = f.height / height;
    FarField c{width, height, std::vector<double>(std::size_t(width) * height, 0.0)};
    for (std::uint32_t row = 0; row < f.height; ++row)
        for (std::uint32_t col = 0; col < f.width; ++col)
            c.lm[std::size_t(row / ky) * width + col / kx] +=
                f.lm[std::size_t(row) * f.width + col];
    return c;
}

double farfield_cell_solid_angle_sr(std::uint32_t row, std::uint32_t width, std::uint32_t height) {
    constexpr double pi = std::numbers::pi;
    const double top = pi / 2 - pi * row / height, bottom = pi / 2 - pi * (row + 1) / height;
    return 2.0 * pi / width * (std::sin(top) - std::sin(bottom));
}

glm::dvec3 farfield_cell_direction(std::uint32_t column, std::uint32_t row, std::uint32_t width,
                                   std::uint32_t height) {
    constexpr double pi = std::numbers::pi;
    const double phi = (column + 0.5) / width * 2.0 * pi - pi;
    const double theta = pi / 2.0 - (row + 0.5) / height * pi;
    return {std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta)};
}

} // namespace fird
