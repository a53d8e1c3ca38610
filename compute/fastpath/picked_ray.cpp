#include "picked_ray.hpp"

#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace fird {

Ray effective_ray(const Scene& scene, std::uint64_t index) {
    const std::uint64_t rays = scene.trace.rays;
    if (index >= rays)
        throw std::invalid_argument(fmt::format(
            "ray {}: past the rayset ({} rays emitted: 0 to {})", index, rays, rays - 1));
    const Ray ray = emit_ray(scene.source, scene.trace.sampler, scene.trace.seed, index, rays);
    if (!ray_meets_box(ray, scene.holder))
        throw std::invalid_argument(fmt::format(
            "ray {}: discarded before tracing (its line misses the holder box)", index));
    return ray;
}

PickedRay trace_picked_ray(FastTracer& tracer, const Scene& scene, std::uint64_t index) {
    PickedRay p{.index = index, .ray = effective_ray(scene, index)};
    // One ray through the bounce loop: the walk-recording pipeline records its walks.
    auto paths = tracer.trace_paths({p.ray}, 0, &p.walk, index);
    p.path = std::move(paths.front());
    p.path.ray_index = index;
    return p;
}

nlohmann::json picked_ray_json(const PickedRay& p) {
    const auto xyz = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    nlohmann::json path = nlohmann::json::array();
    for (const glm::dvec3& v : p.path.vertices)
        path.push_back(xyz(v));
    return {{"index", p.index},
            {"origin_mm", xyz(p.ray.origin)},
            {"direction", xyz(p.ray.direction)},
            {"path_mm", path},
            {"reflections", p.path.reflections},
            {"walk", walk_json(p.walk)}};
}

} // namespace fird
