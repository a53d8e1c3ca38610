#include "source_outline.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "model/source.hpp"
#include "model/source_clearance.hpp"

namespace fird {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Quads (a, b, c, d) of a grid with `columns` vertices per row, closed around the row.
void add_band(SourceOutline& o, std::uint32_t first_row, std::uint32_t rows,
              std::uint32_t columns) {
    for (std::uint32_t r = 0; r + 1 < rows; ++r)
        for (std::uint32_t k = 0; k < columns; ++k) {
            const std::uint32_t a = first_row + r * columns + k;
            const std::uint32_t b = first_row + r * columns + (k + 1) % columns;
            o.triangles.push_back({a, a + columns, b + columns});
            o.triangles.push_back({a, b + columns, b});
        }
}

} // namespace

SourceOutline source_outline(const SourceDesc& s, double point_radius_mm, int around) {
    const gpu::emission::Emitter e = emitter_of(s);
    const glm::dvec3 y_axis = glm::cross(e.axis, e.x_axis);
    const auto columns = std::uint32_t(around);
    SourceOutline o;
    switch (s.kind) {
    case SourceKind::Cylinder: {
        const gpu::emission::Basis f = gpu::emission::basis_about(e.axis);
        for (int end = 0; end < 2; ++end)
            for (int k = 0; k < around; ++k) {
                const double phi = kTwoPi * k / around;
                o.vertices_mm.push_back(s.center_mm + (end - 0.5) * s.length_mm * e.axis +
                                        s.radius_mm * (std::cos(phi) * f.t + std::sin(phi) * f.b));
            }
        add_band(o, 0, 2, columns);
        break;
    }
    case SourceKind::Sphere:
    case SourceKind::Point: {
        const double r = s.kind == SourceKind::Sphere ? s.radius_mm : point_radius_mm;
        const int rings = std::max(2, around / 2);
        for (int ring = 0; ring <= rings; ++ring)
            for (int k = 0; k < around; ++k) {
                const double theta = std::numbers::pi * ring / rings, phi = kTwoPi * k / around;
                o.vertices_mm.push_back(
                    s.center_mm + r * glm::dvec3(std::sin(theta) * std::cos(phi),
                                                 std::sin(theta) * std::sin(phi), std::cos(theta)));
            }
        add_band(o, 0, std::uint32_t(rings) + 1, columns);
        break;
    }
    case SourceKind::Photometric:
        if (s.radius_mm <= 0.0)
            return source_outline({.kind = SourceKind::Point, .center_mm = s.center_mm},
                                  point_radius_mm, around);
        [[fallthrough]];
    case SourceKind::Disk: {
        // A fan about the centre, wound so that its normal is the emitting side's.
        o.vertices_mm.push_back(s.center_mm);
        for (int k = 0; k < around; ++k) {
            const double phi = kTwoPi * k / around;
            o.vertices_mm.push_back(
                s.center_mm + s.radius_mm * (std::cos(phi) * e.x_axis + std::sin(phi) * y_axis));
        }
        for (std::uint32_t k = 0; k < columns; ++k)
            o.triangles.push_back({0, 1 + k, 1 + (k + 1) % columns});
        break;
    }
    case SourceKind::RayFile: {
        // The box its rays start in (a die's or a package's extent).
        const SourceBox box = source_box(s);
        for (int corner = 0; corner < 8; ++corner)
            o.vertices_mm.push_back({corner & 1 ? box.hi.x : box.lo.x,
                                     corner & 2 ? box.hi.y : box.lo.y,
                                     corner & 4 ? box.hi.z : box.lo.z});
        // Two triangles per face, wound outwards.
        o.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                       {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
        break;
    }
    case SourceKind::Rectangle: {
        for (const auto& [a, b] : {std::pair{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}})
            o.vertices_mm.push_back(s.center_mm + a * s.width_mm * e.x_axis +
                                    b * s.height_mm * y_axis);
        o.triangles = {{0, 1, 2}, {0, 2, 3}};
        break;
    }
    }
    return o;
}

} // namespace fird
