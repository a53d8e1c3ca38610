#version 450
// Atomic histogram of integer keys; keys out of range land in the extra last bin,
// so nothing is lost silently.
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_BIN_KEYS_WORKGROUP_SIZE) in;
layout(std430, binding = kBinKeysBindingKeys) readonly buffer Keys { uint keys[]; };
layout(std430, binding = kBinKeysBindingBins) buffer Bins { uint bins[]; };
layout(push_constant) uniform Push { BinKeysPush pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    const uint key = keys[i];
    atomicAdd(bins[min(key, pc.bin_count)], 1u);
}
