#version 450
// The far field in lumens (§4.4): every ray carries flux / rays_emitted lumens, and keeps
// the share R^k of it after k reflections off a reflector of reflectance R (material.h):
// layer k of the counts holds the rays that left after k reflections (one layer, R^0,
// where every ray weighs the same).
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_REDUCE_WORKGROUP_SIZE) in;
// The counts through an R32UI texel view: CPU drivers load a storage buffer at a per-lane
// index lane by lane, each value stored into a stack copy of the vector that is then read
// back whole (a stalled store-to-load forward per value), where an image load is one
// gather (docs/architecture.md, "Far fields as texels").
layout(binding = kToLmBindCounts, r32ui) uniform readonly uimageBuffer counts;
layout(std430, binding = kToLmBindLumens) writeonly buffer Lumens { float lm[]; };
// The lumens four cells at a time where the far field is a whole number of vec4s (count a
// multiple of 4, so the last vec4 stays inside the buffer): CPU drivers store a storage
// buffer lane by lane, a vec4 for what a float costs.
layout(std430, binding = kToLmBindLumens) writeonly buffer Lumens4 { vec4 lm4[]; };
layout(push_constant) uniform Push { ToLmPush pc; };

// Invocation q converts cells 4q to 4q + 3.
void main() {
    const uint q = gl_GlobalInvocationID.x;
    const uint i = 4u * q;
    if (i >= pc.count) return;
    // Cells past the last are never stored; their loads stay inside the view (the last
    // cell's, read again): a texel past a view's end is undefined without robustness.
    const uvec4 cells = min(uvec4(i) + uvec4(0u, 1u, 2u, 3u), uvec4(pc.count - 1u));
    vec4 sum = vec4(0.0);
    float weight = pc.lm_per_ray;
    for (uint k = 0u; k < pc.layers; ++k) { // bounded: layers <= FIRD_MAX_REFLECTIONS + 1
        const ivec4 at = ivec4(uvec4(k * pc.count) + cells);
        const uvec4 n = uvec4(imageLoad(counts, at.x).r, imageLoad(counts, at.y).r,
                              imageLoad(counts, at.z).r, imageLoad(counts, at.w).r);
        sum += vec4(n) * weight;
        weight *= pc.reflectance;
    }
    if (pc.count % 4u == 0u) {
        lm4[q] = sum;
        return;
    }
    for (uint c = 0u; c < 4u && i + c < pc.count; ++c) lm[i + c] = sum[c];
}
