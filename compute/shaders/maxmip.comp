#version 450
// One level of the max-mip quadtree (§4.2): each node holds the maximum height of the
// texels below it. Sizes need not be powers of two: a parent at (i, j) covers the
// children (2i..2i+1, 2j..2j+1) that exist. The refined pyramid's level 0 bounds the
// bilinear surface over each texel (it mixes in the neighbours' samples); higher levels
// of both pyramids are plain maxima.
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
        // The bilinear surface over this texel is four quarter patches, each spanning the
        // texel centre, two edge midpoints and a corner; a bilinear patch is largest at a
        // corner, so the maximum is among the centre, the edge midpoints (mean of two
        // samples) and the corners (mean of four). Much tighter than the 3 x 3 maximum on
        // steep walls, where it halves the candidate texels that turn out not to be hits.
        float n[9];
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const ivec2 q = clamp(ivec2(p) + ivec2(dx, dy), ivec2(0), ivec2(w - 1u, h - 1u));
                n[(dy + 1) * 3 + dx + 1] = paper[uint(q.y) * w + uint(q.x)];
            }
        const float c = n[4];
        float m = c;
        m = max(m, max(max(0.5 * (c + n[3]), 0.5 * (c + n[5])), max(0.5 * (c + n[1]), 0.5 * (c + n[7]))));
        m = max(m, max(0.25 * (c + n[3] + n[1] + n[0]), 0.25 * (c + n[5] + n[1] + n[2])));
        m = max(m, max(0.25 * (c + n[3] + n[7] + n[6]), 0.25 * (c + n[5] + n[7] + n[8])));
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
