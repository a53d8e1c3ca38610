// Packing a scene into the GPU's SceneParams (shaders/fird_shared.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "fird_shared.h"
#include "model/scene.hpp"

namespace fird {

struct QuadtreeLayout {
    std::uint32_t levels = 0;
    std::uint32_t w[FIRD_MAX_LEVELS] = {};
    std::uint32_t h[FIRD_MAX_LEVELS] = {};
    std::uint32_t offset[FIRD_MAX_LEVELS] = {};
    std::uint64_t total_floats = 0;
};

// Levels until a 1 x 1 root; a parent covers ceil(w / 2) x ceil(h / 2) children.
QuadtreeLayout quadtree_layout(std::uint32_t width, std::uint32_t height);

// The origin of the fast path's frame: the holder box's centre. Every position the
// device sees (holder, source, family centres and heights, mesh vertices, rays) is
// relative to it, so float32 keeps its precision wherever the scene sits (a holder at
// 1e5 mm has absolute coordinates whose ulp is 8e-3 mm, but relative ones of its own
// size); directions and the far field do not change.
glm::dvec3 frame_origin(const Holder& holder);

// The reflector-independent part: source, holder, sampler, grids, bounce settings, in
// the frame of frame_origin(scene.holder).
gpu::SceneParams scene_params(const Scene& scene, std::uint64_t seed);
// The shader family id of a reflector family (meshes: heights uploaded or rasterized).
std::uint32_t gpu_family(Family family);
// The far field's layers of counts (SceneParams.farfield_layers): one per reflection order
// where the reflector's reflectance is below 1, else one.
std::uint32_t farfield_layers(const Scene& s);
// The specialization constants of the fast-path pipelines (FIRD_SPEC_* ids).
std::array<std::uint32_t, FIRD_SPEC_COUNT> specialization(const gpu::SceneParams& params,
                                                          Family family);
// Adds the reflector (family and parameters, positions moved into the frame of `origin`);
// returns B-spline control heights if any (in that frame).
std::vector<float> set_reflector_params(gpu::SceneParams& params, const ReflectorDesc& reflector,
                                        const glm::dvec3& origin);

} // namespace fird
