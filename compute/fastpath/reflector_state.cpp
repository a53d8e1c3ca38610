#include "reflector_state.hpp"

#include <span>
#include <vector>

#include <fmt/format.h>

#include "fastpath/scene_params.hpp"

namespace fird {

// A uniform buffer (common.glsl): Vulkan guarantees 16 KiB of one.
static_assert(sizeof(gpu::SceneParams) <= 16384);

namespace {

std::uint64_t quadtree_bytes(const gpu::SceneParams& p) {
    return quadtree_layout(p.hf_w, p.hf_h).total_floats * 4;
}
std::uint64_t gradients_bytes(const gpu::SceneParams& p) {
    return std::uint64_t(p.hf_w) * p.hf_h * 8;
}
std::uint64_t corners_bytes(const gpu::SceneParams& p) {
    return std::uint64_t(p.hf_w + 1) * (p.hf_h + 1) * 4;
}
std::uint64_t farfield_bytes(const gpu::SceneParams& p) {
    return std::uint64_t(p.ff_w) * p.ff_h * 4;
}

// The counts hold a layer per reflection order where the reflectance is below 1.
std::uint64_t farfield_counts_bytes(const gpu::SceneParams& p) {
    return farfield_bytes(p) * p.farfield_layers;
}

} // namespace

ReflectorState make_reflector_state(const vk::Context& ctx, const gpu::SceneParams& params,
                                    const std::string& prefix) {
    const auto storage = vk::kStorageUsage;
    const auto name = [&](const char* what) { return fmt::format("{}.{}", prefix, what); };
    // Also vertex buffers: the viewport draws the height field straight from them; and
    // image buffers: the trace reads the quadtree and the heights with imageLoad.
    const auto tree_usage = storage | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                            VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                            VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    ReflectorState s;
    s.name = prefix;
    s.params = params;
    s.params_buffer =
        vk::Buffer(ctx, sizeof(gpu::SceneParams), storage | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                   vk::MemoryUse::Upload, name("params"));
    s.control = make_float_table(ctx, 1, vk::MemoryUse::Device, name("bspline.control"));
    s.walk_start = vk::Buffer(ctx, 4, storage, vk::MemoryUse::Device, name("walk_start"));
    s.paper_tree = vk::Buffer(ctx, quadtree_bytes(params), tree_usage, vk::MemoryUse::Device,
                              name("quadtree.paper"));
    s.refined_tree = vk::Buffer(ctx, quadtree_bytes(params), tree_usage, vk::MemoryUse::Device,
                                name("quadtree.refined"));
    s.gradients = vk::Buffer(ctx, gradients_bytes(params), tree_usage, vk::MemoryUse::Device,
                             name("normals"));
    s.corners = vk::Buffer(ctx, corners_bytes(params), tree_usage, vk::MemoryUse::Device,
                           name("heights.corners"));
    s.paper_view =
        vk::TexelView(ctx, s.paper_tree, VK_FORMAT_R32_SFLOAT, name("quadtree.paper.view"));
    s.refined_view =
        vk::TexelView(ctx, s.refined_tree, VK_FORMAT_R32_SFLOAT, name("quadtree.refined.view"));
    s.gradients_view =
        vk::TexelView(ctx, s.gradients, VK_FORMAT_R32G32_SFLOAT, name("normals.view"));
    s.corners_view =
        vk::TexelView(ctx, s.corners, VK_FORMAT_R32_SFLOAT, name("heights.corners.view"));
    s.farfield_counts = vk::Buffer(ctx, farfield_counts_bytes(params),
                                   storage | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT,
                                   vk::MemoryUse::Device, name("farfield.counts"));
    s.farfield_counts_view =
        vk::TexelView(ctx, s.farfield_counts, VK_FORMAT_R32_UINT, name("farfield.counts.view"));
    s.farfield_lm = make_float_table(ctx, std::uint64_t(params.ff_w) * params.ff_h,
                                     vk::MemoryUse::Device, name("farfield.lm"));
    return s;
}

std::uint64_t reflector_state_bytes(const gpu::SceneParams& p) {
    return sizeof(gpu::SceneParams) + 8 + 2 * quadtree_bytes(p) + gradients_bytes(p) +
           corners_bytes(p) + farfield_bytes(p) + farfield_counts_bytes(p);
}

bool set_state_reflector(const vk::Context& ctx, ReflectorState& state,
                         const gpu::SceneParams& scene_params, const ReflectorDesc& reflector,
                         const glm::dvec3& origin) {
    if (state.reflector && *state.reflector == reflector) return false; // height field current
    state.params = scene_params;
    const std::vector<float> control = set_reflector_params(state.params, reflector, origin);
    if (!control.empty()) {
        if (state.control.values.size() != control.size() * 4)
            state.control = make_float_table(ctx, control.size(), vk::MemoryUse::Device,
                                             state.name + ".bspline.control");
        state.control.values.upload(ctx, std::span<const float>(control));
    }
    state.params_buffer.upload(ctx, std::as_bytes(std::span(&state.params, 1)));
    state.reflector = reflector;
    state.heightfield_dirty = true;
    return true;
}

} // namespace fird
