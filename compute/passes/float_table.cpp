#include "passes/float_table.hpp"

#include <algorithm>
#include <string>

namespace fird {

FloatTable make_float_table(const vk::Context& ctx, std::uint64_t count, vk::MemoryUse use,
                            std::string_view name) {
    vk::require_texel_count(ctx, std::max<std::uint64_t>(count, 1), name);
    FloatTable t;
    t.values = vk::Buffer(ctx, std::max<std::uint64_t>(count, 1) * sizeof(float),
                          vk::kStorageUsage | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT, use, name);
    t.texels = vk::TexelView(ctx, t.values, VK_FORMAT_R32_SFLOAT, std::string(name) + ".texels");
    return t;
}

} // namespace fird
