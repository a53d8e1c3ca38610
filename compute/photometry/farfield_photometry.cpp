#include "farfield_photometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace fird {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// [a, b] cut at the nodes strictly inside it (nodes repeat every `period` if > 0).
std::vector<double> cut(double a, double b, const std::vector<double>& nodes, double period) {
    std::vector<double> points{a};
    for (double shift :
         period > 0.0 ? std::vector<double>{-period, 0.0, period} : std::vector<double>{0.0})
        for (double n : nodes)
            if (n + shift > a && n + shift < b) points.push_back(n + shift);
    points.push_back(b);
    std::sort(points.begin(), points.end());
    return points;
}

// Whether `step` divides `range` into whole intervals.
bool divides(double range, double step) {
    const double n = range / step;
    return step > 0.0 && std::abs(n - std::round(n)) < 1e-9 * n;
}
} // namespace

glm::dvec3 scene_direction(double c_deg, double gamma_deg) {
    const double s = std::sin(gamma_deg * kDeg);
    return {s * std::cos(c_deg * kDeg), -s * std::sin(c_deg * kDeg), std::cos(gamma_deg * kDeg)};
}

FarField farfield_from_table(const CandelaTable& table, std::uint32_t width, std::uint32_t height) {
    FarField ff{width, height, std::vector<double>(std::size_t(width) * height, 0.0)};
    // Per column: the C sub-intervals (mid C, width in radians); per row: the gamma
    // sub-intervals (mid gamma in cos, width in cos). The model is bilinear in (C,
    // cos gamma) inside each piece, so area x midpoint value is its exact integral.
    struct Piece {
        double mid_deg;
        double measure;
    };
    std::vector<std::vector<Piece>> columns(width), rows(height);
    const std::vector<double> c_nodes =
        table.c_deg.size() > 1 ? table.c_deg : std::vector<double>{};
    for (std::uint32_t i = 0; i < width; ++i) {
        const double c0 = 180.0 - 360.0 * (i + 1) / width, c1 = 180.0 - 360.0 * i / width;
        const auto p = cut(c0, c1, c_nodes, 360.0);
        for (std::size_t k = 0; k + 1 < p.size(); ++k)
            columns[i].push_back({0.5 * (p[k] + p[k + 1]), (p[k + 1] - p[k]) * kDeg});
    }
    for (std::uint32_t j = 0; j < height; ++j) {
        const double g0 = 180.0 * j / height, g1 = 180.0 * (j + 1) / height;
        const auto p = cut(g0, g1, table.gamma_deg, 0.0);
        for (std::size_t k = 0; k + 1 < p.size(); ++k) {
            const double u0 = std::cos(p[k] * kDeg), u1 = std::cos(p[k + 1] * kDeg);
            const double mid = std::acos(std::clamp(0.5 * (u0 + u1), -1.0, 1.0)) / kDeg;
            if (mid < table.gamma_deg.front() || mid > table.gamma_deg.back()) continue;
            rows[j].push_back({mid, u0 - u1});
        }
    }
    for (std::uint32_t j = 0; j < height; ++j)
        for (const Piece& g : rows[j])
            for (std::uint32_t i = 0; i < width; ++i)
                for (const Piece& c : columns[i])
                    ff.lm[std::size_t(j) * width + i] +=
                        c.measure * g.measure * intensity_cd(table, c.mid_deg, g.mid_deg);
    return ff;
}

CandelaTable table_from_farfield(const FarField& ff, double c_step, double g_step,
                                 double* flux_correction) {
    if (!divides(360.0, c_step) || !divides(180.0, g_step))
        throw std::invalid_argument(
            fmt::format("C step {} and gamma step {} must divide 360 and 180 deg", c_step, g_step));
    if (c_step < 360.0 / ff.width || g_step < 180.0 / ff.height)
        throw std::invalid_argument(fmt::format(
            "C step {} or gamma step {} is finer than the far field's cells ({} x {} deg)", c_step,
            g_step, 360.0 / ff.width, 180.0 / ff.height));
    const auto nc = std::size_t(std::lround(360.0 / c_step));
    const auto ng = std::size_t(std::lround(180.0 / g_step)) + 1;
    std::vector<double> lm(nc * ng, 0.0), sr(nc * ng, 0.0);
    // Each node gathers the solid angle within half a step of it (gamma 0 and 180 half a
    // window). A cell across a window's edge is split by solid angle, its lumens taken as
    // spread evenly over it: where a step is an odd number of cells, the cells on a
    // window's edge are shared, not given whole to the outer node (which put nadir's light
    // half a cell out, and read 0 cd at nadir with one cell a step).
    const double cell_c = 360.0 / ff.width;
    for (std::uint32_t j = 0; j < ff.height; ++j) {
        const double g0 = 180.0 * j / ff.height, g1 = 180.0 * (j + 1) / ff.height;
        const double band_sr = std::cos(g0 * kDeg) - std::cos(g1 * kDeg); // per radian of C
        // The gamma nodes whose windows this band meets, and the share of it in each.
        std::vector<std::pair<std::size_t, double>> g_parts; // node, sr per radian of C
        const auto g_first = std::size_t(std::max(0.0, std::floor(g0 / g_step + 0.5)));
        for (std::size_t g = g_first; g < ng && (double(g) - 0.5) * g_step < g1; ++g) {
            const double a = std::max(g0, (double(g) - 0.5) * g_step);
            const double b = std::min(g1, (double(g) + 0.5) * g_step);
            if (b > a) g_parts.push_back({g, std::cos(a * kDeg) - std::cos(b * kDeg)});
        }
        for (std::uint32_t i = 0; i < ff.width; ++i) {
            // The cell's C interval (C = -phi, measured from C0 = +x), unwrapped.
            const double c_lo = 180.0 - 360.0 * (i + 1) / ff.width;
            const double cell_lm = ff.lm[std::size_t(j) * ff.width + i];
            const auto c_first = std::floor(c_lo / c_step + 0.5);
            for (double n = c_first; (n - 0.5) * c_step < c_lo + cell_c; n += 1.0) {
                const double a = std::max(c_lo, (n - 0.5) * c_step);
                const double b = std::min(c_lo + cell_c, (n + 0.5) * c_step);
                if (!(b > a)) continue;
                const auto c = std::size_t((std::llround(n) % std::int64_t(nc) + std::int64_t(nc)) %
                                           std::int64_t(nc));
                const double c_share = (b - a) / cell_c;
                for (const auto& [g, part_sr] : g_parts) {
                    lm[c * ng + g] += cell_lm * c_share * part_sr / band_sr;
                    sr[c * ng + g] += part_sr * (b - a) * kDeg;
                }
            }
        }
    }
    CandelaTable t;
    t.format = "farfield";
    t.version = "FIRD far field";
    t.symmetry = Symmetry::None;
    t.absolute = true;
    for (std::size_t c = 0; c < nc; ++c)
        t.c_deg.push_back(double(c) * c_step);
    for (std::size_t g = 0; g < ng; ++g)
        t.gamma_deg.push_back(double(g) * g_step);
    t.n_horizontal = nc;
    t.n_vertical = ng;
    t.cd.resize(nc * ng);
    for (std::size_t k = 0; k < t.cd.size(); ++k)
        t.cd[k] = sr[k] > 0.0 ? lm[k] / sr[k] : 0.0;
    const double total = ff.total_lm();
    const double flux = integrated_flux_lm(t);
    const double factor = flux > 0.0 ? total / flux : 1.0;
    for (double& v : t.cd)
        v *= factor;
    if (flux_correction) *flux_correction = factor;
    t.flux_declared_lm = total;
    return t;
}

} // namespace fird
