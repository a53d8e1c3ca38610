#version 450
// The far field in lumens (§4.4): every ray carries flux / rays_emitted lumens, and keeps
// the share R^k of it after k reflections off a reflector of reflectance R (material.h):
// layer k of the counts holds the rays that left after k reflections (one layer, R^0,
// where every ray weighs the same).
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_REDUCE_WORKGROUP_SIZE) in;
layout(std430, binding = kToLmBindCounts) readonly buffer Counts { uint counts[]; };
layout(std430, binding = kToLmBindLumens) writeonly buffer Lumens { float lm[]; };
layout(push_constant) uniform Push { ToLmPush pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    float sum = 0.0;
    float weight = pc.lm_per_ray;
    for (uint k = 0u; k < pc.layers; ++k) { // bounded: layers <= FIRD_MAX_REFLECTIONS + 1
        sum += float(counts[k * pc.count + i]) * weight;
        weight *= pc.reflectance;
    }
    lm[i] = sum;
}
