#version 450
// The height texture (§4.2): the reflector evaluated at each texel centre of a W x H
// grid over the holder rectangle, clamped to the holder's z range, with its gradient
// (the normal texture); and at the (W + 1) x (H + 1) texel corners, where the refined
// hit mode's bilinear surface takes its heights (one bilinear patch per texel).
// B-splines read their control heights. Meshes are rasterized instead
// (fastpath/mesh_raster.cpp).
#extension GL_GOOGLE_include_directive : require
#include "family.glsl"

layout(local_size_x = FIRD_HEIGHTFIELD_WORKGROUP_SIZE, local_size_y = FIRD_HEIGHTFIELD_WORKGROUP_SIZE) in;
layout(std430, binding = kHeightfieldBindHeights) buffer Heights { float heights[]; };
layout(std430, binding = kHeightfieldBindGradients) writeonly buffer Gradients { vec2 gradients[]; };
// The control heights through an R32F texel view: read at per-lane indices, a storage
// buffer's loads would run lane by lane on CPU drivers (16 a B-spline evaluation).
layout(binding = kHeightfieldBindControl, r32f) uniform readonly imageBuffer control;
layout(std430, binding = kHeightfieldBindCorners) writeonly buffer Corners { float corners[]; };

layout(constant_id = FIRD_SPEC_REFINED_ONLY) const uint kRefinedOnly = 0u;

float control_height(int k) { return imageLoad(control, k).r; }

vec3 surface(vec2 xy) { return reflector_height_gradient(xy); }

// Invocation p evaluates texel p's low corner and (unless kRefinedOnly) its centre, where
// there is one.
void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x > P.hf_w || p.y > P.hf_h) return;
    const vec3 lo = holder_min(), hi = holder_max();
    const vec2 texel = (hi.xy - lo.xy) / vec2(P.hf_w, P.hf_h);
    corners[p.y * (P.hf_w + 1u) + p.x] = clamp(surface(lo.xy + vec2(p) * texel).x, lo.z, hi.z);
    if (kRefinedOnly != 0u || p.x == P.hf_w || p.y == P.hf_h) return;
    const uint index = p.y * P.hf_w + p.x;
    const vec3 zg = surface(lo.xy + (vec2(p) + 0.5) * texel);
    const bool plateau = zg.x <= lo.z || zg.x >= hi.z; // clamped: flat
    heights[index] = clamp(zg.x, lo.z, hi.z);
    gradients[index] = plateau ? vec2(0.0) : zg.yz;
}
