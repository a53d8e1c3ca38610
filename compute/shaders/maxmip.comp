#version 450
// One level of the max-mip quadtree (§4.2): each node holds the maximum height of the
// texels below it. Sizes need not be powers of two: a parent at (i, j) covers the
// children (2i..2i+1, 2j..2j+1) that exist. The refined pyramid's level 0 is the 3 x 3
// dilation of the heights, since the bilinear surface over a texel reaches its
// neighbours' centres; higher levels of both pyramids are plain maxima.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = FIRD_HEIGHTFIELD_WORKGROUP_SIZE, local_size_y = FIRD_HEIGHTFIELD_WORKGROUP_SIZE) in;
layout(std430, binding = kMaxMipBindPaper) buffer Paper { float paper[]; };
layout(std430, binding = kMaxMipBindRefined) buffer Refined { float refined[]; };
layout(push_constant) uniform Push { MaxMipPush pc; };

void main() {
    const uint level = pc.level;
    const uvec2 p = gl_GlobalInvocationID.xy;
    const uint w = P.level_w[level], h = P.level_h[level];
    if (p.x >= w || p.y >= h) return;
    const uint out_index = P.level_offset[level] + p.y * w + p.x;
    if (level == 0u) {
        float m = -3.0e38;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const ivec2 q = clamp(ivec2(p) + ivec2(dx, dy), ivec2(0), ivec2(w - 1u, h - 1u));
                m = max(m, paper[uint(q.y) * w + uint(q.x)]);
            }
        refined[out_index] = m;
        return;
    }
    const uint cw = P.level_w[level - 1u], ch = P.level_h[level - 1u];
    const uint base = P.level_offset[level - 1u];
    float mp = -3.0e38, mr = -3.0e38;
    for (uint dy = 0u; dy < 2u; ++dy)
        for (uint dx = 0u; dx < 2u; ++dx) {
            const uvec2 c = 2u * p + uvec2(dx, dy);
            if (c.x >= cw || c.y >= ch) continue;
            mp = max(mp, paper[base + c.y * cw + c.x]);
            mr = max(mr, refined[base + c.y * cw + c.x]);
        }
    paper[out_index] = mp;
    refined[out_index] = mr;
}
