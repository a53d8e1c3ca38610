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
layout(std430, binding = kReduceBindingPartial) writeonly buffer Partial { float partial[]; };
layout(std430, binding = kReduceBindingRowWeight) readonly buffer RowWeight { float row_weight[]; };
layout(push_constant) uniform Push { ReducePush pc; };
layout(constant_id = FIRD_SPEC_REDUCE_MODE) const uint kMode = kReduceSum;

// One partial sum per subgroup: a subgroup reduction in place of a shared-memory tree
// (CPU drivers suspend every subgroup of the workgroup at each barrier: one barrier here,
// where the tree had nine). The first invocation adds the subgroups' sums in order, which
// holds for subgroups of any size, full or not (tests/reduction_bound.hpp: the roundings).
shared float sums[kReduceWorkgroupSize];

void main() {
    const uint span = kReduceWorkgroupSize * kReduceItemsPerThread;
    const uint base = gl_WorkGroupID.x * span + gl_LocalInvocationID.x;
    float s = 0.0;
    for (uint k = 0u; k < kReduceItemsPerThread; ++k) {
        const uint i = base + k * kReduceWorkgroupSize;
        if (i < pc.count) {
            if (kMode == kReduceSquaredDifference) {
                const float d = a[i] - b[i];
                s += d * d;
            } else if (kMode == kReduceCandelaSquaredDifference) {
                const float d = a[i] - b[i];
                // 1 / (4 pi omega) for the row's cells (farfield.hpp metric_cell_weight, in
                // double on the host: ReducePass's row weights).
                s += d * d * row_weight[i / pc.width];
            } else {
                s += a[i];
            }
        }
    }
    s = subgroupAdd(s);
    if (subgroupElect()) sums[gl_SubgroupID] = s;
    barrier();
    if (gl_LocalInvocationID.x == 0u) {
        float t = sums[0];
        for (uint k = 1u; k < gl_NumSubgroups; ++k) t += sums[k];
        partial[gl_WorkGroupID.x] = t;
    }
}
