// The stratified sampler: Philox4x32-10 with its first two uniforms stratified along a Morton
// curve over a 2^b x 2^b grid (b = kStratumBits), so that consecutive rays fall in the same
// or a neighbouring cell. A source whose direction depends on those two uniforms alone
// (sphere, cylinder, point, disk, rectangle) then emits its rayset already ordered by
// direction, as the trace wants it (fird_shared.h, rayset_ordered_at_birth). The GPU's twin
// is common.glsl ray_uniforms.
#pragma once

#include <array>
#include <cstdint>

#include "fird_shared.h"
#include "philox.hpp"

namespace fird {

using gpu::kStrata;
using gpu::kStrataBits;
using gpu::kStratumOffsetBits;

// The even bits of x gathered into its low half (the inverse of a Morton spread).
constexpr std::uint32_t compact_bits(std::uint32_t x) {
    x &= 0x55555555u;
    x = (x | (x >> 1)) & 0x33333333u;
    x = (x | (x >> 2)) & 0x0f0f0f0fu;
    x = (x | (x >> 4)) & 0x00ff00ffu;
    x = (x | (x >> 8)) & 0x0000ffffu;
    return x;
}

// The stratum of ray `index` of `rays`: floor((index K + s) / rays) for K strata and s
// uniform in [0, K). Over the rayset the values index K + s fall in stratum c's interval
// [c rays, (c + 1) rays) with total probability rays / K, so every stratum gets its share
// on average for any ray count (unbiased), and the stratum never decreases with the index.
// Exact for index < 2^(64 - kStrataBits).
constexpr std::uint32_t stratum(std::uint64_t index, std::uint64_t rays, std::uint32_t s) {
    return std::uint32_t(((index << kStrataBits) | s) / rays);
}

// Four uniforms in (0, 1) for ray `index` of `rays` under `seed`: the first two stratified
// (as above, uniform inside the cell), the last two Philox's own.
inline std::array<double, 4> stratified_uniforms(std::uint64_t seed, std::uint64_t index,
                                                 std::uint64_t rays) {
    const Philox4 w = philox4x32_10({std::uint32_t(index), std::uint32_t(index >> 32), 0u, 0u},
                                    {std::uint32_t(seed), std::uint32_t(seed >> 32)});
    const std::uint32_t c = stratum(index, rays, w[0] >> (32 - kStrataBits));
    constexpr std::uint32_t kOffsetMask = (1u << kStratumOffsetBits) - 1u;
    const std::uint32_t x =
        (compact_bits(c) << kStratumOffsetBits) | (w[1] >> (32 - kStratumOffsetBits));
    const std::uint32_t y = (compact_bits(c >> 1) << kStratumOffsetBits) |
                            ((w[1] >> (32 - 2 * kStratumOffsetBits)) & kOffsetMask);
    return {(double(x) + 0.5) * 0x1p-23, (double(y) + 0.5) * 0x1p-23,
            (double(w[2]) + 0.5) * 0x1p-32, (double(w[3]) + 0.5) * 0x1p-32};
}

} // namespace fird
