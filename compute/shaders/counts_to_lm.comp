#version 450
// The far field in lumens (§4.4): every ray carries flux / rays_emitted lumens.
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_REDUCE_WORKGROUP_SIZE) in;
layout(std430, binding = 0) readonly buffer Counts { uint counts[]; };
layout(std430, binding = 1) writeonly buffer Lumens { float lm[]; };
layout(push_constant) uniform Push { uint count; float lm_per_ray; } pc;

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i < pc.count) lm[i] = float(counts[i]) * pc.lm_per_ray;
}
