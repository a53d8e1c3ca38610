// Triangle-mesh reflectors into the height texture by the graphics pipeline: the
// paper's z-buffer step (§4.2), an orthographic view from above on the shared device.
#pragma once

#include <cstdint>

#include "model/mesh.hpp"
#include "model/scene.hpp"
#include "vk/buffer.hpp"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"

namespace fird {

class MeshRasterizer {
  public:
    explicit MeshRasterizer(const vk::Context& ctx);

    // Draws `mesh` over the holder rectangle into a width x height texture (texel
    // centres sampled, highest surface kept) and copies the heights (mm, clamped to the
    // holder's z range) into the first width * height floats of `heights` and the face
    // gradients (dz/dx, dz/dy) into `gradients`. Positions and heights are taken relative
    // to `origin` (the fast path's frame, scene_params.hpp). Waits for the device.
    void rasterize(const TriangleMesh& mesh, const glm::dvec3& origin, const Holder& holder,
                   std::uint32_t width, std::uint32_t height, const vk::Buffer& heights,
                   const vk::Buffer& gradients) const;

  private:
    const vk::Context* ctx_;
    vk::GraphicsPipeline pipeline_;
};

} // namespace fird
