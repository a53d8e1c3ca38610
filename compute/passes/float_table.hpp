// A table of floats on the device (a far field in lumens, a desired far field, a reduction's
// partial sums, a metric's row weights, a B-spline's control heights, an emitter's table):
// the buffer and the R32_SFLOAT storage texel view through which the passes read it.
#pragma once

#include <cstdint>
#include <string_view>

#include "vk/buffer.hpp"

namespace fird {

// Why a view: llvmpipe loads a storage buffer at a per-lane index as a loop over the lanes
// that stores each value into a stack copy of the vector and reads the vector back (a
// stalled store-to-load forward per value), where an image load is one vectorized gather;
// a real GPU reads either in one load (docs/architecture.md, "Far fields as texels").
struct FloatTable {
    vk::Buffer values;
    vk::TexelView texels;
};

// A table of `count` floats (room for one at least: a view needs a texel); throws
// std::invalid_argument naming `name` and the device's texel-buffer limit where they would
// pass it (vk::require_texel_count), before allocating.
FloatTable make_float_table(const vk::Context& ctx, std::uint64_t count, vk::MemoryUse use,
                            std::string_view name);

} // namespace fird
