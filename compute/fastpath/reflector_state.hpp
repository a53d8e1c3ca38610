// One reflector as the fast path traces it: its parameters on the device, its height field
// (the paper's and the refined max-mip quadtrees, the gradients, the corner heights), the
// level the walk starts at and the far field its rays reach. A tracer keeps one for its
// current reflector and, for a batch of candidates in one submission, one per candidate.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

#include "fird_shared.h"
#include "model/scene.hpp"
#include "passes/float_table.hpp"
#include "vk/buffer.hpp"

namespace fird {

struct ReflectorState {
    std::string name;          // its buffers' debug names begin with it ("fird", "fird.candidate3")
    gpu::SceneParams params{}; // the scene's, with this reflector's family and parameters
    std::optional<ReflectorDesc> reflector;
    bool heightfield_dirty = true; // the reflector changed since its height field was built
    // Its height field was built without the paper's products (the texel-centre heights and
    // gradients, the paper quadtree): a refined trace of an analytic family reads neither.
    bool paper_tree_stale = true;
    vk::Buffer params_buffer;
    FloatTable control;    // B-spline control heights (a placeholder for other families)
    vk::Buffer walk_start; // uint: the level the source's rays start their walk at
    vk::Buffer paper_tree, refined_tree, gradients;
    vk::Buffer corners; // the refined surface's heights at the (W + 1) x (H + 1) texel corners
    vk::TexelView paper_view, refined_view, gradients_view, corners_view; // as the trace reads
    vk::Buffer farfield_counts;
    vk::TexelView farfield_counts_view; // as counts_to_lm.comp reads the counts
    FloatTable farfield_lm;
};

// The buffers of one reflector on the height field and far field of `params`, named
// `prefix`.quadtree.paper and so on (the tracer's own: "fird").
ReflectorState make_reflector_state(const vk::Context& ctx, const gpu::SceneParams& params,
                                    const std::string& prefix);

// The device memory one reflector state takes (a batch's candidates within the budget).
std::uint64_t reflector_state_bytes(const gpu::SceneParams& params);

// Makes `reflector` the state's (parameters uploaded, height field marked for a rebuild) on
// the scene's `scene_params` and the device frame at `origin`; false when it is already.
bool set_state_reflector(const vk::Context& ctx, ReflectorState& state,
                         const gpu::SceneParams& scene_params, const ReflectorDesc& reflector,
                         const glm::dvec3& origin);

} // namespace fird
