#version 450
// One level of a tree reduction: each workgroup sums kReduceWorkgroupSize *
// kReduceItemsPerThread inputs into one partial sum. The host repeats the pass on the
// partials until one value is left (the paper's "reduction shader", §4.4).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "fird_shared.h"

layout(local_size_x = FIRD_REDUCE_WORKGROUP_SIZE) in;
layout(std430, binding = kReduceBindingA) readonly buffer A { float a[]; };
layout(std430, binding = kReduceBindingB) readonly buffer B { float b[]; };
// The same inputs read four at a time (the bindings' offsets are 256-byte aligned): CPU
// drivers load a storage buffer at a per-lane index in a loop over the lanes, so a vec4
// load costs what a float's did (the compare of a 1800 x 900 far field: ~5 ms on lavapipe,
// most of it those loops). The last, partial vec4 is read float by float.
layout(std430, binding = kReduceBindingA) readonly buffer A4 { vec4 a4[]; };
layout(std430, binding = kReduceBindingB) readonly buffer B4 { vec4 b4[]; };
layout(std430, binding = kReduceBindingPartial) writeonly buffer Partial { float partial[]; };
layout(std430, binding = kReduceBindingRowWeight) readonly buffer RowWeight { float row_weight[]; };
layout(push_constant) uniform Push { ReducePush pc; };
layout(constant_id = FIRD_SPEC_REDUCE_MODE) const uint kMode = kReduceSum;

// One partial sum per subgroup: a subgroup reduction in place of a shared-memory tree
// (CPU drivers suspend every subgroup of the workgroup at each barrier: one barrier here,
// where the tree had nine). The first invocation adds the subgroups' sums in order, which
// holds for subgroups of any size, full or not (tests/reduction_bound.hpp: the roundings).
shared float sums[kReduceWorkgroupSize];

// Input i's term: itself, or its squared difference from b[i] (weighted by its row's
// 1 / (4 pi omega) for the candela metric: farfield.hpp metric_cell_weight, in double on
// the host, ReducePass's row weights).
float term(uint i, float ai, float bi) {
    if (kMode == kReduceSum) return ai;
    const float d = ai - bi;
    return kMode == kReduceCandelaSquaredDifference ? d * d * row_weight[i / pc.width] : d * d;
}

void main() {
    // The workgroup's span of kReduceWorkgroupSize * kReduceItemsPerThread inputs, as vec4s:
    // each invocation sums kReduceItemsPerThread / 4 of them, lane by lane consecutive.
    const uint quads = kReduceItemsPerThread / 4u;
    const uint base = gl_WorkGroupID.x * kReduceWorkgroupSize * quads + gl_LocalInvocationID.x;
    vec4 s4 = vec4(0.0);
    for (uint k = 0u; k < quads; ++k) {
        const uint q = base + k * kReduceWorkgroupSize;
        const uint i = 4u * q;
        if (i + 3u < pc.count) {
            const vec4 av = a4[q];
            const vec4 bv = kMode == kReduceSum ? vec4(0.0) : b4[q];
            for (uint c = 0u; c < 4u; ++c) s4[c] += term(i + c, av[c], bv[c]);
        } else {
            for (uint c = 0u; c < 3u; ++c) // the last inputs, fewer than four
                if (i + c < pc.count) s4[c] += term(i + c, a[i + c], kMode == kReduceSum ? 0.0 : b[i + c]);
        }
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
