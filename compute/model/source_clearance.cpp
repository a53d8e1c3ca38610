#include "source_clearance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "model/ray_file_source.hpp"
#include "model/source.hpp"

namespace fird {

namespace {
// A ray file's rays start in its origins' box (its file frame): the box of that box's
// corners, placed in the scene.
SourceBox ray_file_box(const SourceDesc& s) {
    if (!s.ray_file.index) throw std::invalid_argument("a ray file source without its index");
    const RayFileIndex& index = *s.ray_file.index;
    const gpu::emission::Emitter e = emitter_of(s);
    const glm::dvec3 y_axis = glm::cross(e.axis, e.x_axis);
    SourceBox box{glm::dvec3(std::numeric_limits<double>::infinity()),
                  glm::dvec3(-std::numeric_limits<double>::infinity())};
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1 ? index.origin_max_mm : index.origin_min_mm).x,
                           (corner & 2 ? index.origin_max_mm : index.origin_min_mm).y,
                           (corner & 4 ? index.origin_max_mm : index.origin_min_mm).z);
        const glm::dvec3 q = e.center + p.x * e.x_axis + p.y * y_axis + p.z * e.axis;
        box.lo = glm::min(box.lo, q);
        box.hi = glm::max(box.hi, q);
    }
    return box;
}
} // namespace

SourceBox source_box(const SourceDesc& s) {
    if (s.kind == SourceKind::RayFile) return ray_file_box(s);
    // Half extents along axis k: a cylinder of axis a reaches L/2 |a_k| + r sqrt(1 - a_k^2);
    // a disk of normal n r sqrt(1 - n_k^2); a rectangle w/2 |x_k| + h/2 |y_k| with x, y its
    // sides' directions; a sphere r; a point 0.
    const gpu::emission::Emitter e = emitter_of(s);
    const glm::dvec3 y_axis = glm::cross(e.axis, e.x_axis);
    glm::dvec3 half(0.0);
    for (int k = 0; k < 3; ++k) {
        const double across = std::sqrt(std::max(0.0, 1.0 - e.axis[k] * e.axis[k]));
        switch (s.kind) {
        case SourceKind::Cylinder:
            half[k] = 0.5 * s.length_mm * std::abs(e.axis[k]) + s.radius_mm * across;
            break;
        case SourceKind::Disk:
        case SourceKind::Photometric:
            half[k] = s.radius_mm * across;
            break;
        case SourceKind::Rectangle:
            half[k] =
                0.5 * s.width_mm * std::abs(e.x_axis[k]) + 0.5 * s.height_mm * std::abs(y_axis[k]);
            break;
        case SourceKind::Sphere:
            half[k] = s.radius_mm;
            break;
        case SourceKind::Point:
        case SourceKind::RayFile: // its origins' box (above)
            break;
        }
    }
    return {s.center_mm - half, s.center_mm + half};
}

double source_clearance_mm(const Surface& surface, const SourceDesc& source) {
    const SourceBox box = source_box(source);
    const Holder& h = surface.holder();
    const double x0 = std::max(box.lo.x, h.min_mm.x), x1 = std::min(box.hi.x, h.max_mm.x);
    const double y0 = std::max(box.lo.y, h.min_mm.y), y1 = std::min(box.hi.y, h.max_mm.y);
    if (x0 > x1 || y0 > y1) return std::numeric_limits<double>::infinity();
    // The height range is conservative: it may refuse a reflector that only nearly
    // touches the source, never accept one that cuts it.
    return box.lo.z - surface.bounds(x0, x1, y0, y1).hi;
}

void check_reflector_clear_of_source(const Surface& surface, const SourceDesc& source) {
    const double clearance = source_clearance_mm(surface, source);
    if (clearance <= 0.0) {
        const double lowest = source_box(source).lo.z;
        throw std::invalid_argument(fmt::format(
            "the reflector cuts the light source: the surface reaches z = {:.3f} mm under the "
            "source, whose lowest point is z = {:.3f} mm",
            lowest - clearance, lowest));
    }
}

} // namespace fird
