// Philox4x32-10 (Salmon et al., "Parallel random numbers: as easy as 1, 2, 3", 2011):
// a counter-based generator. The key is the seed and the counter is (ray index,
// stream), so a ray's random numbers depend only on (seed, index): the same for any
// thread or batch count, and independent across seeds (no XOR-ed hashes).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace fird {

using Philox4 = std::array<std::uint32_t, 4>;

constexpr Philox4 philox4x32_10(Philox4 counter, std::array<std::uint32_t, 2> key) {
    constexpr std::uint32_t kM0 = 0xD2511F53u;
    constexpr std::uint32_t kM1 = 0xCD9E8D57u;
    constexpr std::uint32_t kW0 = 0x9E3779B9u;
    constexpr std::uint32_t kW1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const std::uint64_t p0 = std::uint64_t(kM0) * counter[0];
        const std::uint64_t p1 = std::uint64_t(kM1) * counter[2];
        counter = {std::uint32_t(p1 >> 32) ^ counter[1] ^ key[0], std::uint32_t(p1),
                   std::uint32_t(p0 >> 32) ^ counter[3] ^ key[1], std::uint32_t(p0)};
        key[0] += kW0;
        key[1] += kW1;
    }
    return counter;
}

// Four uniform numbers in (0, 1) for ray `index` of stream `stream` under `seed`.
inline std::array<double, 4> philox_uniforms(std::uint64_t seed, std::uint64_t index,
                                             std::uint32_t stream) {
    const Philox4 bits =
        philox4x32_10({std::uint32_t(index), std::uint32_t(index >> 32), stream, 0u},
                      {std::uint32_t(seed), std::uint32_t(seed >> 32)});
    std::array<double, 4> u{};
    // Midpoints of 2^32 equal cells: never exactly 0 or 1.
    for (int i = 0; i < 4; ++i)
        u[i] = (double(bits[i]) + 0.5) * 0x1p-32;
    return u;
}

// Two independent standard normals from two uniforms in (0, 1) (Box-Muller).
inline std::pair<double, double> standard_normals(double u1, double u2) {
    const double r = std::sqrt(-2.0 * std::log(u1));
    const double a = 2.0 * std::numbers::pi * u2;
    return {r * std::cos(a), r * std::sin(a)};
}

} // namespace fird
