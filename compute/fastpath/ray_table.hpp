// A table of rays on the device: the buffer (common.glsl's Ray, two vec4s per ray, as the
// host packs and reads them) and the RGBA32UI storage texel view through which every pass
// reads and writes it, ray i being texels 2i and 2i + 1 (integer texels: the bits go
// through as they are, FIRD_LOAD_RAY in common.glsl).
#pragma once

#include <cstdint>
#include <string_view>

#include "fird_shared.h"
#include "vk/buffer.hpp"

namespace fird {

// Why a view: llvmpipe loads a storage buffer at a per-lane index as a loop over the lanes,
// each component bounds-checked apart (~80 instructions per lane for a vec4), where an image
// load is one vectorized gather per component; a real GPU reads either in one load
// (docs/architecture.md, "Rays as texels").
struct RayTable {
    vk::Buffer rays;
    vk::TexelView texels;
};

// A table for ray_count rays (at least one); throws std::invalid_argument naming the
// device's texel-buffer limit where the rays' texels would pass it.
RayTable make_ray_table(const vk::Context& ctx, std::uint64_t ray_count, vk::MemoryUse use,
                        std::string_view name);

} // namespace fird
