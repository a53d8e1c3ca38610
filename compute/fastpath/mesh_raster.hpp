// Triangle-mesh reflectors into a height field: the paper's z-buffer step (§4.2), an
// orthographic view from above, as a compute pass on the shared device (mesh_raster.comp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "fird_shared.h"
#include "model/mesh.hpp"
#include "model/scene.hpp"
#include "vk/buffer.hpp"
#include "vk/context.hpp"
#include "vk/typed_pass.hpp"

namespace fird {

// mesh_raster.comp's bindings by name (vk::TypedPass).
struct MeshRasterBindings {
    vk::Binding triangles, items, height_keys, owners, heights, gradients;
    static constexpr auto fields() {
        using B = MeshRasterBindings;
        constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        return std::array<vk::BindingField<B>, 6>{{
            {gpu::kMeshRasterBindTriangles, kStorage, &B::triangles},
            {gpu::kMeshRasterBindItems, kStorage, &B::items},
            {gpu::kMeshRasterBindHeightKeys, kStorage, &B::height_keys},
            {gpu::kMeshRasterBindOwners, kStorage, &B::owners},
            {gpu::kMeshRasterBindHeights, kStorage, &B::heights},
            {gpu::kMeshRasterBindGradients, kStorage, &B::gradients},
        }};
    }
};

// What the pass reads, laid out on the host: each triangle that is not vertical as three
// corners (counter-clockwise seen from above, the plane's gradient in the first two w) and
// its bounding box over the width x height texels tiling [lo, hi] cut along a grid of
// kMeshRasterTile-texel tiles, an item each, marked where no other triangle reaches the
// tile.
struct MeshRasterInput {
    std::vector<glm::vec4> corners;
    std::vector<glm::uvec4> items;
};
MeshRasterInput mesh_raster_input(const TriangleMesh& mesh, const glm::dvec3& origin,
                                  const glm::dvec2& lo, const glm::dvec2& hi, std::uint32_t width,
                                  std::uint32_t height);

class MeshRasterizer {
  public:
    explicit MeshRasterizer(const vk::Context& ctx);

    // Rasters `mesh` over the holder rectangle into width x height texels (texel centres
    // sampled, highest surface kept) and writes the heights (mm, clamped to the holder's z
    // range) into the first width * height floats of `heights` and the face gradients
    // (dz/dx, dz/dy) into `gradients`. Positions and heights are taken relative to
    // `origin` (the fast path's frame, scene_params.hpp). Waits for the device.
    void rasterize(const TriangleMesh& mesh, const glm::dvec3& origin, const Holder& holder,
                   std::uint32_t width, std::uint32_t height, const vk::Buffer& heights,
                   const vk::Buffer& gradients) const;

  private:
    const vk::Context* ctx_;
    vk::TypedPass<MeshRasterBindings, gpu::MeshRasterPush> pass_;
};

} // namespace fird
