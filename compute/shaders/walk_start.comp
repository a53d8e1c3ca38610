#version 450
// Where the walks of the rays leaving the source begin (the trace's first bounce).
// Algorithm 1 starts at the quadtree root and goes down, without advancing along the ray,
// through every node whose height is at or above the ray's start: the ray is below it,
// whichever way it points. For a start inside the source's bounding box (clipped to the
// holder) this holds at every level where each node over the box's footprint reaches
// the box's top; by the max-mip property it then holds at every coarser level too. This
// finds the finest such level L and stores L - 1 (or 0): a walk that begins there makes
// the same decisions as one from the root, less those descents. Nodes over the footprint
// are checked level by level from the root, and only while a level has at most
// kWalkStartMaxNodes of them (the search stops early rather than scan a large source).
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = 1) in;
layout(std430, binding = kWalkStartBindPyramid) readonly buffer Pyramid { float pyramid[]; };
layout(std430, binding = kWalkStartBindLevel) writeonly buffer Start { uint start_level; };

// Every node of `level` over the texel range lo..hi reaches z.
bool all_nodes_reach(uint level, uvec2 lo, uvec2 hi, float z) {
    const uvec2 a = lo >> level, b = hi >> level;
    if ((b.x - a.x + 1u) * (b.y - a.y + 1u) > kWalkStartMaxNodes) return false;
    for (uint y = a.y; y <= b.y; ++y)
        for (uint x = a.x; x <= b.x; ++x)
            if (pyramid[P.level_offset[level] + y * P.level_w[level] + x] < z) return false;
    return true;
}

void main() {
    const uint top = P.levels - 1u;
    start_level = top;
    const vec3 lo = max(vec3(P.source_box_min[0], P.source_box_min[1], P.source_box_min[2]), holder_min());
    const vec3 hi = min(vec3(P.source_box_max[0], P.source_box_max[1], P.source_box_max[2]), holder_max());
    if (any(greaterThan(lo, hi))) return; // the source lies outside the holder box
    const vec2 texel_mm = (holder_max().xy - holder_min().xy) / vec2(P.hf_w, P.hf_h);
    const uvec2 last = uvec2(P.hf_w - 1u, P.hf_h - 1u);
    const uvec2 t0 = min(uvec2(max((lo.xy - holder_min().xy) / texel_mm, vec2(0.0))), last);
    const uvec2 t1 = min(uvec2(max((hi.xy - holder_min().xy) / texel_mm, vec2(0.0))), last);
    uint level = top + 1u;
    while (level > 0u && all_nodes_reach(level - 1u, t0, t1, hi.z)) --level;
    // The finest level whose nodes all reach the top is `level` (none: top + 1).
    if (level <= top) start_level = level > 0u ? level - 1u : 0u;
}
