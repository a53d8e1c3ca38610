#version 450
// The rayset (§4.1): sample the source, keep the rays whose forward half-line meets the
// holder box (appended, then ordered by direction), count the others as discarded.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "direction_bucket.glsl"

layout(local_size_x = FIRD_RAYSET_WORKGROUP_SIZE) in;
layout(std430, binding = kRaysetBindRays) writeonly buffer Rays { Ray rays[]; };
layout(std430, binding = kRaysetBindCounters) buffer Counters { uint counters[]; };
layout(std430, binding = kRaysetBindBuckets) buffer Buckets { uint buckets[]; };
layout(push_constant) uniform Push { RaysetPush pc; };

void main() {
    const uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    const uint lo = pc.first_lo + i;
    const uint hi = pc.first_hi + (lo < pc.first_lo ? 1u : 0u);
    const Ray r = sample_source(ray_uniforms(lo, hi));
    vec2 t01;
    const bool effective =
        clip_to_box(r.origin.xyz, r.direction.xyz, holder_min(), holder_max(), t01) || pc.keep_all != 0u;
    FIRD_COUNT(counters, kCounterDiscarded, !effective);
    uint slot;
    FIRD_APPEND_INDEX(counters, kCounterEffective, effective, slot);
    if (effective) {
        rays[slot] = r;
        atomicAdd(buckets[direction_bucket(r.direction.xyz)], 1u); // for rayset_order.comp
    }
}
