// A flat mirror under a source, and the cosine law's share of a far-field row: the answers
// worked out by hand that the emitter and material tests check both tracers against.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "io/scene_file.hpp"
#include "model/scene.hpp"
#include "model/source.hpp"

namespace fird::test {

// A flat mirror z = -10 mm over a 200 x 200 mm holder; the source above it, pointing down.
inline Scene mirror_scene(const SourceDesc& source, std::uint64_t rays) {
    Scene s = parse_scene(R"(
[source]
type = "point"
center_mm = [0.0, 0.0, 0.0]
flux_lm = 100.0
[holder]
min_mm = [-100.0, -100.0, -12.0]
max_mm = [100.0, 100.0, 2.0]
[reflector]
family = "plane"
z0 = -10.0
sx = 0.0
sy = 0.0
cx = 0.0
cy = 0.0
[trace]
rays = 1000
seed = 3
max_bounces = 1
farfield = [72, 36]
heightfield = [64, 64]
)",
                          "mirror.toml");
    s.source = source;
    s.trace.rays = rays;
    return s;
}

// The flux of each row of a w x h far field (lm).
inline std::vector<double> far_field_rows_lm(const std::vector<double>& lm, std::uint32_t w,
                                             std::uint32_t h) {
    std::vector<double> rows(h, 0.0);
    for (std::uint32_t row = 0; row < h; ++row)
        for (std::uint32_t c = 0; c < w; ++c)
            rows[row] += lm[std::size_t(row) * w + c];
    return rows;
}

// The fraction of a Lambertian emitter's flux, mirrored to leave about the zenith, that
// falls in far-field row `row`: (1/pi) times the integral of cos(gamma) dOmega over the
// row, with gamma the angle from the zenith and e = pi/2 - gamma the elevation:
// (1/pi) 2 pi [sin^2 e / 2] from e_bottom to e_top = sin^2 e_top - sin^2 e_bottom.
inline double cosine_law_row_fraction(std::uint32_t row, std::uint32_t rows) {
    const double top = std::numbers::pi / 2 - std::numbers::pi * row / rows;
    const double bottom = std::numbers::pi / 2 - std::numbers::pi * (row + 1) / rows;
    const auto sin2 = [](double e) { return e > 0 ? std::sin(e) * std::sin(e) : 0.0; };
    return sin2(top) - sin2(bottom);
}

// How many rays of two lists (the fast path's rayset, in float, and the CPU's rays, in
// double) are equal to `tolerance` in origin and direction, both sorted by direction
// (near-equal x components may sort apart between float and double: a few unmatched).
inline std::size_t rays_matching(std::vector<Ray> a, std::vector<Ray> b, double tolerance) {
    const auto by_direction = [](const Ray& p, const Ray& q) {
        return std::tie(p.direction.x, p.direction.y, p.direction.z) <
               std::tie(q.direction.x, q.direction.y, q.direction.z);
    };
    std::sort(a.begin(), a.end(), by_direction);
    std::sort(b.begin(), b.end(), by_direction);
    std::size_t matched = 0;
    for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
        if (glm::length(a[i].direction - b[i].direction) < tolerance &&
            glm::length(a[i].origin - b[i].origin) < tolerance)
            ++matched;
    return matched;
}

} // namespace fird::test
