// What the fast tracer's files share (fast_tracer_*.cpp): descriptor kinds, sizes and
// small helpers. Private to compute/fastpath.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <initializer_list>

#include "fastpath/pass_bindings.hpp"
#include "fird_shared.h"

namespace fird::fast_tracer_detail {

inline constexpr std::uint64_t kRayBytes = gpu::kRayTexels * 16; // fastpath/ray_table.hpp
// trace.comp's HitRecord: (hit point, t), (reflected direction, texel bits), (next slot + 1).
inline constexpr std::uint64_t kHitRecordVec4s = 3;
inline constexpr std::uint64_t kHitRecordBytes = kHitRecordVec4s * 16;
inline constexpr std::uint64_t kCountersBytes =
    std::uint64_t(gpu::kTallyCopies) * gpu::kCounterCount * 4;
// The most device memory a kept rayset may take (1e7 emitted rays take at most 320 MB).
inline constexpr std::uint64_t kRaysetCacheBytes = 1ull << 30;
// Rays per batch of a ray file source (fast_tracer.cpp).
inline constexpr std::uint64_t kRayFileBatchRays = 1ull << 20;

inline std::uint32_t groups(std::uint64_t n, std::uint32_t size) {
    return std::uint32_t((n + size - 1) / size);
}

inline double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// 64-bit sums kept on the device as (low, high) pairs of uints.
inline std::uint64_t wide(const std::uint32_t* pair) {
    return std::uint64_t(pair[0]) | (std::uint64_t(pair[1]) << 32);
}

// trace.comp's pass (fast_tracer_bounces.cpp; its bindings in pass_bindings.hpp).
// `variant` lists the specialization constants (FIRD_SPEC_RECORD_WALK, _PROFILE,
// _DIAGNOSTICS) switched on over the scene's; `bounce_kind` the rays it takes
// (gpu::kBounceEither: any bounce's, by its number).
passes::TracePass trace_pipeline(const vk::Context& ctx,
                                 std::array<std::uint32_t, FIRD_SPEC_COUNT> spec,
                                 std::initializer_list<int> variant, const char* name,
                                 std::uint32_t bounce_kind = gpu::kBounceEither);

} // namespace fird::fast_tracer_detail
