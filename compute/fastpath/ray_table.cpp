#include "fastpath/ray_table.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "vk/context.hpp"

namespace fird {

RayTable make_ray_table(const vk::Context& ctx, std::uint64_t ray_count, vk::MemoryUse use,
                        std::string_view name) {
    const std::uint64_t rays = std::max<std::uint64_t>(ray_count, 1);
    vk::require_texel_count(ctx, rays * gpu::kRayTexels,
                            fmt::format("a table of {} rays ({} texels a ray: trace fewer at once)",
                                        rays, gpu::kRayTexels));
    RayTable t;
    t.rays = vk::Buffer(ctx, rays * gpu::kRayTexels * 16,
                        vk::kStorageUsage | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT, use, name);
    t.texels =
        vk::TexelView(ctx, t.rays, VK_FORMAT_R32G32B32A32_UINT, std::string(name) + ".texels");
    return t;
}

} // namespace fird
