#include "camera.hpp"

#include <algorithm>
#include <cmath>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace fird::render {

OrbitCamera frame_holder(const Holder& h) {
    OrbitCamera c;
    c.target = 0.5 * (h.min_mm + h.max_mm);
    const double radius = 0.5 * glm::length(h.max_mm - h.min_mm);
    c.distance_mm = radius / std::sin(0.5 * c.fov_deg * M_PI / 180.0) * 1.05;
    return c;
}

glm::dvec3 camera_position(const OrbitCamera& c) {
    const double az = c.azimuth_deg * M_PI / 180.0, el = c.elevation_deg * M_PI / 180.0;
    return c.target + c.distance_mm * glm::dvec3(std::cos(el) * std::cos(az),
                                                 std::cos(el) * std::sin(az), std::sin(el));
}

namespace {
glm::dvec3 up_for(const OrbitCamera& c) {
    return std::abs(c.elevation_deg) > 89.0 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
}
} // namespace

glm::mat4 view_projection(const OrbitCamera& c, double aspect) {
    const glm::dvec3 eye = camera_position(c);
    const glm::dmat4 view = glm::lookAt(eye, c.target, up_for(c));
    const double near = std::max(1e-3, c.distance_mm * 0.02), far = c.distance_mm * 4.0;
    glm::dmat4 proj = glm::perspectiveRH_ZO(c.fov_deg * M_PI / 180.0, aspect, near, far);
    proj[1][1] *= -1.0; // Vulkan's y points down the image
    return glm::mat4(proj * view);
}

PixelRay pixel_ray(const OrbitCamera& c, double px, double py, double w, double h) {
    const glm::dmat4 inv = glm::inverse(glm::dmat4(view_projection(c, w / h)));
    const double x = 2.0 * (px + 0.5) / w - 1.0, y = 2.0 * (py + 0.5) / h - 1.0;
    const glm::dvec4 a = inv * glm::dvec4(x, y, 0.0, 1.0), b = inv * glm::dvec4(x, y, 1.0, 1.0);
    const glm::dvec3 pa = glm::dvec3(a) / a.w, pb = glm::dvec3(b) / b.w;
    return {pa, glm::normalize(pb - pa)};
}

} // namespace fird::render
