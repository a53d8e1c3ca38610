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
// The same buffers four cells at a time: CPU drivers load and store a storage buffer at a
// per-lane index in a loop over the lanes, so a vec4 costs what a float did. Used where
// every layer starts on a vec4 (count a multiple of 4); cells past the last whole vec4,
// and every cell otherwise, go one at a time.
layout(std430, binding = kToLmBindCounts) readonly buffer Counts4 { uvec4 counts4[]; };
layout(std430, binding = kToLmBindLumens) writeonly buffer Lumens4 { vec4 lm4[]; };
layout(push_constant) uniform Push { ToLmPush pc; };

// Invocation q converts cells 4q to 4q + 3.
void main() {
    const uint q = gl_GlobalInvocationID.x;
    const uint i = 4u * q;
    if (i >= pc.count) return;
    if (pc.count % 4u == 0u) {
        vec4 sum = vec4(0.0);
        float weight = pc.lm_per_ray;
        for (uint k = 0u; k < pc.layers; ++k) { // bounded: layers <= FIRD_MAX_REFLECTIONS + 1
            sum += vec4(counts4[k * (pc.count / 4u) + q]) * weight;
            weight *= pc.reflectance;
        }
        lm4[q] = sum;
        return;
    }
    for (uint c = 0u; c < 4u && i + c < pc.count; ++c) {
        float sum = 0.0;
        float weight = pc.lm_per_ray;
        for (uint k = 0u; k < pc.layers; ++k) {
            sum += float(counts[k * pc.count + i + c]) * weight;
            weight *= pc.reflectance;
        }
        lm[i + c] = sum;
    }
}
