#version 450
// The bounce loop's bookkeeping between two passes, by one invocation: how many rays the
// next pass traces or orders, and the indirect dispatch sizes for it (ceil(rays /
// workgroup) groups). It replaces the host's readback of the rays a bounce appended, so
// every bounce of a batch is recorded into one command buffer. A bounce without rays gets
// 0 groups: its indirect dispatch costs next to nothing (the skip of empty bounces).
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = 1) in;
layout(std430, binding = kBounceArgsBindCounters) buffer Counters { uint counters[]; };
layout(std430, binding = kBounceArgsBindLoop) buffer Loop { uint loop_state[]; };
layout(push_constant) uniform Push { BounceArgsPush pc; };

uint groups_for(uint rays, uint size) {
    return min((rays + size - 1u) / size, pc.groups_max);
}

void set_args(uint at, uint groups) {
    loop_state[at] = groups;
    loop_state[at + 1u] = 1u;
    loop_state[at + 2u] = 1u;
}

void main() {
    if (pc.stage == kArgsOrderRayset) {
        // The rayset is always sorted when it does not come ordered (the order of its
        // effective rays is the trace's, however few).
        const uint n = counters[kCounterEffective];
        loop_state[kLoopOrderCount] = n;
        loop_state[kLoopSort] = 1u;
        set_args(kLoopScanArgs, n > 0u ? 1u : 0u);
        set_args(kLoopOrderArgs, groups_for(n, FIRD_RAYSET_WORKGROUP_SIZE));
        return;
    }
    uint n;
    if (pc.stage == kArgsFirstBounce) {
        n = counters[kCounterEffective];
    } else {
        // The rays the bounce before appended; they are ordered by direction (or, when
        // too few for it to pay, copied in order) into the next bounce's input.
        n = counters[kCounterActiveOut];
        const bool sort = loop_state[kLoopActive] >= kOrderMinRays;
        loop_state[kLoopOrderCount] = n;
        loop_state[kLoopSort] = sort ? 1u : 0u;
        set_args(kLoopScanArgs, sort && n > 0u ? 1u : 0u);
        set_args(kLoopOrderArgs, groups_for(n, FIRD_RAYSET_WORKGROUP_SIZE));
    }
    counters[kCounterActiveOut] = 0u; // the next bounce appends from slot 0
    loop_state[kLoopActive] = n;
    loop_state[kLoopBounceRays + pc.bounce] = n;
    const uint groups = groups_for(n, FIRD_TRACE_WORKGROUP_SIZE);
    set_args(kLoopTraceArgs, groups == 0u && pc.trace_empty != 0u ? 1u : groups);
}
