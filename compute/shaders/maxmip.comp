#version 450
// One level of the max-mip quadtree (§4.2): each node holds the maximum height of the
// texels below it. Sizes need not be powers of two: a parent at (i, j) covers the
// children (2i..2i+1, 2j..2j+1) that exist. The refined pyramid's level 0 bounds the
// bilinear patch over each texel: the largest of its four corner heights (a bilinear
// patch is largest at a corner); higher levels of both pyramids are plain maxima.
#extension GL_GOOGLE_include_directive : require
#include "common.glsl"

layout(local_size_x = FIRD_HEIGHTFIELD_WORKGROUP_SIZE, local_size_y = FIRD_HEIGHTFIELD_WORKGROUP_SIZE) in;
layout(std430, binding = kMaxMipBindPaper) writeonly buffer Paper { float paper[]; };
layout(std430, binding = kMaxMipBindRefined) writeonly buffer Refined { float refined[]; };
// What a level reads: R32F image-buffer views of the corners and of the two pyramids (the
// level below, written by the dispatch before). CPU drivers gather an image load for all
// lanes at once, inlined (a texel fetch is a call to a function that does the same);
// storage-buffer loads at per-lane indices run a scalar loop per lane.
layout(binding = kMaxMipBindCorners, r32f) uniform readonly imageBuffer corners;
layout(binding = kMaxMipBindPaperIn, r32f) uniform readonly imageBuffer paper_in;
layout(binding = kMaxMipBindRefinedIn, r32f) uniform readonly imageBuffer refined_in;
layout(push_constant) uniform Push { MaxMipPush pc; };
layout(constant_id = FIRD_SPEC_MAXMIP_LEVEL_ZERO) const uint kLevelZero = 0u;
layout(constant_id = FIRD_SPEC_REFINED_ONLY) const uint kRefinedOnly = 0u;

void main() {
    const uint level = pc.level;
    const uvec2 p = gl_GlobalInvocationID.xy;
    const uint w = P.level_w[level], h = P.level_h[level];
    if (p.x >= w || p.y >= h) return;
    const uint out_index = P.level_offset[level] + p.y * w + p.x;
    if (kLevelZero != 0u) {
        const int row = int(w + 1u), c = int(p.y) * row + int(p.x);
        const float m = max(max(imageLoad(corners, c).r, imageLoad(corners, c + 1).r),
                            max(imageLoad(corners, c + row).r, imageLoad(corners, c + row + 1).r));
        // A margin above float rounding of the interpolation in trace.comp.
        refined[out_index] = m + 1e-5 * (abs(m) + 1.0);
        return;
    }
    const uint cw = P.level_w[level - 1u], ch = P.level_h[level - 1u];
    const uint base = P.level_offset[level - 1u];
    // The children that exist (a last odd row or column has one): a missing one reads
    // its existing neighbour again, which leaves the maximum as it is.
    const uvec2 c0 = 2u * p, c1 = min(c0 + 1u, uvec2(cw, ch) - 1u);
    const int i00 = int(base + c0.y * cw + c0.x), i10 = int(base + c0.y * cw + c1.x);
    const int i01 = int(base + c1.y * cw + c0.x), i11 = int(base + c1.y * cw + c1.x);
    const float mr = max(max(imageLoad(refined_in, i00).r, imageLoad(refined_in, i10).r),
                         max(imageLoad(refined_in, i01).r, imageLoad(refined_in, i11).r));
    refined[out_index] = mr;
    if (kRefinedOnly != 0u) return;
    const float mp = max(max(imageLoad(paper_in, i00).r, imageLoad(paper_in, i10).r),
                         max(imageLoad(paper_in, i01).r, imageLoad(paper_in, i11).r));
    paper[out_index] = mp;
}
