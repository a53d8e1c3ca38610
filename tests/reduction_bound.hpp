// The largest relative error of a device reduction's result (reduce_sum.comp) that float
// rounding alone allows, for a sum of `count` nonnegative terms each carrying at most
// `term_roundings` roundings, on a device whose subgroups have `subgroup_size` lanes: at
// each level of the tree every partial sum passes through at most kReduceItemsPerThread
// serial additions per thread (reduce_sum.comp adds kReduceItemsPerThread / 4 vec4s, then
// the vec4's four lanes pairwise: fewer), subgroup_size - 1 in the subgroup's reduction (a driver
// may add the lanes in order, as CPU drivers do; a tree adds fewer) and one per further subgroup of
// the workgroup (added in order); for nonnegative terms the relative error of the sum is at most
// (term roundings + additions along a path) u, u = 2^-24 (first order). `root`: the bound of the
// square root of that sum (half).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fird_shared.h"

namespace fird::test {

inline double reduction_relative_bound(std::uint64_t count, int term_roundings, bool root,
                                       std::uint32_t subgroup_size) {
    const std::uint64_t span =
        std::uint64_t(gpu::kReduceWorkgroupSize) * gpu::kReduceItemsPerThread;
    int levels = 0;
    for (std::uint64_t n = count; n > 1; n = (n + span - 1) / span)
        ++levels;
    const std::uint32_t lanes = std::clamp(subgroup_size, 1u, gpu::kReduceWorkgroupSize);
    const int per_level = int(gpu::kReduceItemsPerThread) + int(lanes) - 1 +
                          int((gpu::kReduceWorkgroupSize + lanes - 1) / lanes) - 1;
    const double bound = (term_roundings + std::max(levels, 1) * per_level) * std::ldexp(1.0, -24);
    return root ? 0.5 * bound : bound;
}

} // namespace fird::test
