#version 450
// The rayset (§4.1): sample the source, keep the rays whose forward half-line meets the
// holder box, count the others as discarded. The kept rays are appended in emission
// order within a workgroup (a stratified sampler's rays of a sphere, cylinder, point, disk
// or rectangle are thereby in direction order already: fird_shared.h); other rays (a
// photometric source's or a ray file's; independent or Sobol ones) are also counted per
// direction bucket for rayset_order.comp to sort.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"
#include "source.glsl"
#include "direction_bucket.glsl"

layout(local_size_x = FIRD_RAYSET_WORKGROUP_SIZE) in;
layout(binding = kRaysetBindRays, rgba32ui) uniform writeonly uimageBuffer rays;
layout(std430, binding = kRaysetBindCounters) buffer Counters { uint counters[]; };
layout(std430, binding = kRaysetBindBuckets) buffer Buckets { uint buckets[]; };
layout(push_constant) uniform Push { RaysetPush pc; };

shared uint subgroup_first[FIRD_RAYSET_WORKGROUP_SIZE]; // per subgroup: kept rays, then offset
shared uint group_first;                                // the workgroup's first slot in the rayset

void main() {
    const uint i = gl_GlobalInvocationID.x;
    const bool emitted = i < pc.count;
    const uint lo = pc.first_lo + i;
    const uint hi = pc.first_hi + (lo < pc.first_lo ? 1u : 0u);
    // A ray file's rays were read by the host (emitted ones only: i < count).
    Ray r = kSourceKind == kSourceRayFile ? ray_file_ray(emitted ? i : 0u)
                                          : sample_source(ray_uniforms(lo, hi));
    // The ray carries its emission index's low word through every bounce (the high word
    // follows from the batch's first index): the finish's draws are keyed on it.
    r.origin.w = uintBitsToFloat(lo);
    vec2 t01;
    const bool effective =
        emitted && (clip_to_box(r.origin.xyz, r.direction.xyz, holder_min(), holder_max(), t01) ||
                    pc.keep_all != 0u);
    FIRD_COUNT(counters, kCounterDiscarded, emitted && !effective);

    // Slots in emission order: the subgroups' counts are scanned by one invocation, which
    // reserves the workgroup's range with one atomic (the workgroups' ranges may interleave
    // in any order; the far field does not depend on it).
    const uvec4 ballot = subgroupBallot(effective);
    if (subgroupElect()) subgroup_first[gl_SubgroupID] = subgroupBallotBitCount(ballot);
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uint total = 0u;
        for (uint s = 0u; s < gl_NumSubgroups; ++s) {
            const uint n = subgroup_first[s];
            subgroup_first[s] = total;
            total += n;
        }
        group_first = atomicAdd(counters[kCounterEffective], total);
    }
    barrier();
    if (effective) {
        FIRD_STORE_RAY(rays, group_first + subgroup_first[gl_SubgroupID] +
                                 subgroupBallotExclusiveBitCount(ballot), r);
        if (!rayset_ordered_at_birth(kSamplerKind, kSourceKind))
            atomicAdd(buckets[direction_bucket(r.direction.xyz)], 1u); // for rayset_order.comp
    }
}
