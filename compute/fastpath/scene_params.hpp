// Packing a scene into the GPU's SceneParams (shaders/fird_shared.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

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

// The reflector-independent part: source, holder, sampler, grids, bounce settings.
gpu::SceneParams scene_params(const Scene& scene, std::uint64_t seed);
// The shader family id of a reflector family (meshes: heights uploaded or rasterized).
std::uint32_t gpu_family(Family family);
// The specialization constants of the fast-path pipelines (FIRD_SPEC_* ids).
std::array<std::uint32_t, FIRD_SPEC_COUNT> specialization(const gpu::SceneParams& params,
                                                          Family family);
// Adds the reflector (family and parameters); returns B-spline control heights if any.
std::vector<float> set_reflector_params(gpu::SceneParams& params, const ReflectorDesc& reflector);

} // namespace fird
