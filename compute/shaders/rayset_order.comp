#version 450
// Orders the rayset by direction (a counting sort on an octahedral direction grid): rays
// that leave in nearly the same direction become neighbours, so the lanes of a subgroup
// walk the quadtree alike and share cache lines (on SIMD CPU drivers this halves Model
// A's trace). rayset.comp counts the rays per bucket, bucket_scan.comp turns the counts
// into offsets, and this pass moves each ray to its bucket. The order inside a bucket is
// unspecified; the far field does not depend on the order (integer counts). Its count and
// whether to sort come from the bounce loop's state (bounce_args.comp): a bounce's output
// too small to pay for sorting is copied as it is, so the next bounce reads the same buffer
// either way.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = FIRD_RAYSET_WORKGROUP_SIZE) in;
layout(binding = kOrderBindRaysIn, rgba32ui) uniform readonly uimageBuffer rays_in;
layout(binding = kOrderBindRaysOut, rgba32ui) uniform writeonly uimageBuffer rays_out;
layout(std430, binding = kOrderBindBuckets) buffer Buckets { uint buckets[]; };
layout(std430, binding = kOrderBindLoop) readonly buffer Loop { uint loop_state[]; };
layout(push_constant) uniform Push { RaysetOrderPush pc; };

#include "direction_bucket.glsl"

void main() {
    const uint i = gl_GlobalInvocationID.x;
    // Read before the first branch: CPU drivers load a storage buffer in divergent control
    // flow lane by lane, even at an address common to all.
    const uint count = loop_state[kLoopOrderCount];
    const bool sort = loop_state[kLoopSort] != 0u;
    if (i >= count) return;
    const Ray r = FIRD_LOAD_RAY(rays_in, i);
    uint slot = i;
    if (sort) {
        const uint bucket = pc.reflected != 0u ? reflected_bucket(r.origin.xyz, r.direction.xyz) : direction_bucket(r.direction.xyz);
        slot = atomicAdd(buckets[bucket], 1u);
    }
    FIRD_STORE_RAY(rays_out, slot, r);
}
