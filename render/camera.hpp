// An orbit camera as plain data, and the matrices the viewport draws with.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "model/scene.hpp"

namespace fird::render {

struct OrbitCamera {
    glm::dvec3 target{0.0};    // the point it orbits, mm
    double azimuth_deg = -60;  // about +z, from +x
    double elevation_deg = 35; // above the xy plane
    double distance_mm = 100;
    double fov_deg = 35; // vertical
};

// A camera that frames the whole holder box from above one corner.
OrbitCamera frame_holder(const Holder& holder);

glm::dvec3 camera_position(const OrbitCamera& camera);

// Vulkan's clip space: y down the image, depth 0 (near) to 1 (far).
glm::mat4 view_projection(const OrbitCamera& camera, double aspect);

// The world-space ray through pixel (px, py) of a w x h image (for picking).
struct PixelRay {
    glm::dvec3 origin, direction;
};
PixelRay pixel_ray(const OrbitCamera& camera, double px, double py, double w, double h);

} // namespace fird::render
