// A 4-dimensional Sobol sequence with Owen scrambling (nested uniform scrambling by a
// hash, after Burley, "Practical Hash-based Owen Scrambling", JCGT 2020), index-shuffled
// per seed. Point i depends only on (seed, i): deterministic under any batching.
#pragma once

#include <array>
#include <cstdint>

namespace fird {

// Four scrambled Sobol coordinates in (0, 1) for point `index` under `seed`.
std::array<double, 4> sobol_uniforms(std::uint64_t seed, std::uint64_t index);

// The tables behind it, for the GPU twin (shaders/common.glsl): direction numbers of the
// four dimensions, and the Owen scramble seeds (four dimensions, then the index).
struct SobolTables {
    std::uint32_t directions[4][32];
    std::uint32_t scramble[5];
};
SobolTables sobol_tables(std::uint64_t seed);

} // namespace fird
