#version 450
// One level of a tree reduction: each workgroup sums kReduceWorkgroupSize *
// kReduceItemsPerThread inputs into one partial sum. The host repeats the pass on the
// partials until one value is left (the paper's "reduction shader", §4.4).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "fird_shared.h"

layout(local_size_x = FIRD_REDUCE_WORKGROUP_SIZE) in;
// The inputs through R32F texel views: CPU drivers load a storage buffer at a per-lane index
// lane by lane, each value stored into a stack copy of the vector that is then read back
// whole (a stalled store-to-load forward per value: ~3/4 of the compare's time on lavapipe),
// where an image load is one gather (docs/architecture.md, "Far fields as texels").
layout(binding = kReduceBindingA, r32f) uniform readonly imageBuffer a;
layout(binding = kReduceBindingB, r32f) uniform readonly imageBuffer b;
layout(std430, binding = kReduceBindingPartial) writeonly buffer Partial { float partial[]; };
layout(binding = kReduceBindingRowWeight, r32f) uniform readonly imageBuffer row_weight;
layout(push_constant) uniform Push { ReducePush pc; };
layout(constant_id = FIRD_SPEC_REDUCE_MODE) const uint kMode = kReduceSum;

// One partial sum per subgroup: a subgroup reduction in place of a shared-memory tree
// (CPU drivers suspend every subgroup of the workgroup at each barrier: one barrier here,
// where the tree had nine). The first invocation adds the subgroups' sums in order, which
// holds for subgroups of any size, full or not (tests/reduction_bound.hpp: the roundings).
shared float sums[kReduceWorkgroupSize];

// Input i's term (i < count): itself, or its squared difference from b[i] (weighted by its
// row's 1 / (4 pi omega) for the candela metric: farfield.hpp metric_cell_weight, in double
// on the host, ReducePass's row weights).
float term(uint i) {
    const float ai = imageLoad(a, int(pc.a_offset + i)).r;
    if (kMode == kReduceSum) return ai;
    const float d = ai - imageLoad(b, int(i)).r;
    return kMode == kReduceCandelaSquaredDifference
               ? d * d * imageLoad(row_weight, int(i / pc.width)).r
               : d * d;
}

void main() {
    // The workgroup's span of kReduceWorkgroupSize * kReduceItemsPerThread inputs, in runs of
    // four: each invocation sums kReduceItemsPerThread / 4 runs, lane by lane consecutive.
    const uint runs = kReduceItemsPerThread / 4u;
    const uint base = gl_WorkGroupID.x * kReduceWorkgroupSize * runs + gl_LocalInvocationID.x;
    vec4 s4 = vec4(0.0);
    for (uint k = 0u; k < runs; ++k) {
        const uint i = 4u * (base + k * kReduceWorkgroupSize);
        // Past the last input a term is zero, its loads kept inside the views (the last
        // input's, read again; the first where there is none: a table holds one float at
        // least): a texel past a view's end is undefined without robustness.
        const uint last = max(pc.count, 1u) - 1u;
        for (uint c = 0u; c < 4u; ++c) s4[c] += i + c < pc.count ? term(min(i + c, last)) : 0.0;
    }
    float s = (s4.x + s4.y) + (s4.z + s4.w);
    s = subgroupAdd(s);
    if (subgroupElect()) sums[gl_SubgroupID] = s;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        float t = sums[0];
        for (uint k = 1u; k < gl_NumSubgroups; ++k) t += sums[k];
        partial[gl_WorkGroupID.x] = t;
    }
}
