#include "height_modes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include <fmt/format.h>

namespace fird {

namespace {

// The weight of mode (kx, ky): the broad shapes first. Measured on the 36-height freeform
// (docs/optimization.md): exponents 1, 2 and 3 against independent heights.
double mode_weight(std::size_t kx, std::size_t ky) {
    return std::pow(1.0 + double(kx + ky), -2.0);
}

// Entry n of the orthonormal DCT-II basis vector k of length N.
double cosine(std::size_t k, std::size_t n, std::size_t count) {
    const double N = double(count);
    const double a = k == 0 ? std::sqrt(1.0 / N) : std::sqrt(2.0 / N);
    return a * std::cos(std::numbers::pi * (double(n) + 0.5) * double(k) / N);
}

// The space's index of every grid height, column i fastest (nx x ny; a profile's ny = 1);
// none unless every one is free.
std::optional<std::vector<std::size_t>> free_grid(const ReflectorDesc& r, const ParameterSpace& s) {
    const bool profile = r.family == Family::Profile;
    if (r.family != Family::BSpline && !profile) return std::nullopt;
    const std::size_t nx = std::size_t(r.bspline.nx), ny = profile ? 1 : std::size_t(r.bspline.ny);
    if (nx * ny < 2) return std::nullopt;
    std::vector<std::size_t> at;
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) {
            const std::string name =
                profile ? fmt::format("h_{}", i) : fmt::format("h_{}_{}", i, j);
            const auto it = std::find(s.names.begin(), s.names.end(), name);
            if (it == s.names.end()) return std::nullopt;
            // The name must be the grid's point (i, j), not a group of another shape.
            const auto group = r.bspline.groups.find(name);
            if (group == r.bspline.groups.end() ||
                group->second !=
                    ControlGroup{.kind = ControlGroup::Kind::Point, .i = int(i), .j = int(j)})
                return std::nullopt;
            at.push_back(std::size_t(it - s.names.begin()));
        }
    return at;
}

} // namespace

std::vector<double> SampleCoordinates::parameters(const std::vector<double>& c) const {
    if (transform.empty()) return c;
    std::vector<double> x = origin;
    const std::size_t n = size();
    for (std::size_t r = 0; r < n; ++r)
        for (std::size_t k = 0; k < n; ++k)
            x[r] += transform[r * n + k] * c[k];
    return x;
}

SampleCoordinates sample_coordinates(const ReflectorDesc& reflector, const ParameterSpace& space,
                                     const std::vector<double>& start, HeightSampling sampling) {
    const std::size_t n = space.size();
    SampleCoordinates c{.origin = start,
                        .transform = {},
                        .lo = space.lo,
                        .hi = space.hi,
                        .degree = std::vector<std::size_t>(n, 0)};
    const auto grid =
        sampling == HeightSampling::Modes ? free_grid(reflector, space) : std::nullopt;
    if (!grid) return c;
    // With modes every coordinate is an offset from the start: the others' boxes move with
    // it (pagmo reads only their widths, which are the parameters' own).
    for (std::size_t k = 0; k < n; ++k) {
        c.lo[k] = space.lo[k] - start[k];
        c.hi[k] = space.hi[k] - start[k];
    }
    const bool profile = reflector.family == Family::Profile;
    const std::size_t nx = std::size_t(reflector.bspline.nx);
    const std::size_t ny = profile ? 1 : std::size_t(reflector.bspline.ny);
    // Coordinates keep the space's order: the grid's heights' places hold its modes (mode m
    // at the place of the m-th height), the other parameters are themselves.
    c.transform.assign(n * n, 0.0);
    for (std::size_t k = 0; k < n; ++k)
        c.transform[k * n + k] = 1.0;
    double width = 0.0;
    for (const std::size_t p : *grid) {
        width = std::max(width, space.hi[p] - space.lo[p]);
        c.transform[p * n + p] = 0.0;
    }
    // sqrt(N) makes a unit coefficient move the heights by its weight in mm RMS.
    const double scale = std::sqrt(double(nx * ny));
    for (std::size_t m = 0; m < grid->size(); ++m) {
        const std::size_t kx = m % nx, ky = m / nx;
        const double w = mode_weight(kx, ky) * scale;
        c.degree[(*grid)[m]] = kx + ky;
        for (std::size_t h = 0; h < grid->size(); ++h) {
            const std::size_t i = h % nx, j = h / nx;
            c.transform[(*grid)[h] * n + (*grid)[m]] =
                w * cosine(kx, i, nx) * (profile ? 1.0 : cosine(ky, j, ny));
        }
        // Each mode's box as wide as the heights' and centred on the start, so that the
        // first spread (a fraction of the box) is the heights' own.
        c.lo[(*grid)[m]] = -0.5 * width;
        c.hi[(*grid)[m]] = 0.5 * width;
    }
    c.modes = grid->size();
    c.grid = profile ? fmt::format("{}", nx) : fmt::format("{} x {}", nx, ny);
    return c;
}

} // namespace fird
