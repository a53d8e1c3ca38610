// Constants and push-constant structs read by both C++ and GLSL: workgroup sizes,
// binding numbers and push-constant layouts are defined once, here.
// Push-constant structs use only 4-byte scalars so std430 and C++ layouts agree.
#ifndef FIRD_SHARED_H
#define FIRD_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace fird::gpu {
using uint = std::uint32_t;
#define FIRD_CONSTANT(type, name, value) inline constexpr type name = value
#else
#define FIRD_CONSTANT(type, name, value) const type name = value
#endif

// Workgroup sizes are macros so GLSL layout qualifiers and C++ dispatch math share them.
#define FIRD_REDUCE_WORKGROUP_SIZE 256
#define FIRD_BIN_KEYS_WORKGROUP_SIZE 256

// ---- reduce_sum.comp: sum of x, or of (a - b)^2 (the l2 distance's sum) ----
FIRD_CONSTANT(uint, kReduceWorkgroupSize, FIRD_REDUCE_WORKGROUP_SIZE);
FIRD_CONSTANT(uint, kReduceItemsPerThread, 8u);
FIRD_CONSTANT(uint, kReduceBindingA, 0u);      // float[count]
FIRD_CONSTANT(uint, kReduceBindingB, 1u);      // float[count] (mode kReduceSquaredDifference)
FIRD_CONSTANT(uint, kReduceBindingPartial, 2u); // float[groups]
FIRD_CONSTANT(uint, kReduceSum, 0u);
FIRD_CONSTANT(uint, kReduceSquaredDifference, 1u);
struct ReducePush {
    uint count;
    uint mode;
};

// ---- bin_keys.comp: atomic histogram of integer keys ----
FIRD_CONSTANT(uint, kBinKeysWorkgroupSize, FIRD_BIN_KEYS_WORKGROUP_SIZE);
FIRD_CONSTANT(uint, kBinKeysBindingKeys, 0u);  // uint[count]
FIRD_CONSTANT(uint, kBinKeysBindingBins, 1u);  // uint[bin_count + 1]; last slot counts out-of-range keys
struct BinKeysPush {
    uint count;
    uint bin_count;
};

#ifdef __cplusplus
} // namespace fird::gpu
#endif
#endif
