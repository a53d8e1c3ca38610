#version 450
// One level of the max-mip quadtree (§4.2): each node holds the maximum height of the
// texels below it. Sizes need not be powers of two: a parent at (i, j) covers the
// children (2i..2i+1, 2j..2j+1) that exist. The refined pyramid's level 0 bounds the
// bilinear patch over each texel: the largest of its four corner heights (a bilinear
// patch is largest at a corner); higher levels of both pyramids are plain maxima.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = FIRD_HEIGHTFIELD_WORKGROUP_SIZE, local_size_y = FIRD_HEIGHTFIELD_WORKGROUP_SIZE) in;
layout(std430, binding = kMaxMipBindPaper) buffer Paper { float paper[]; };
layout(std430, binding = kMaxMipBindRefined) buffer Refined { float refined[]; };
layout(std430, binding = kMaxMipBindCorners) readonly buffer Corners { float corners[]; };
layout(push_constant) uniform Push { MaxMipPush pc; };

void main() {
    const uint level = pc.level;
    const uvec2 p = gl_GlobalInvocationID.xy;
    const uint w = P.level_w[level], h = P.level_h[level];
    if (p.x >= w || p.y >= h) return;
    const uint out_index = P.level_offset[level] + p.y * w + p.x;
    if (level == 0u) {
        const uint row = w + 1u, c = p.y * row + p.x;
        const float m = max(max(corners[c], corners[c + 1u]), max(corners[c + row], corners[c + row + 1u]));
        // A margin above float rounding of the interpolation in trace.comp.
        refined[out_index] = m + 1e-5 * (abs(m) + 1.0);
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
