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
layout(std430, binding = kHeightfieldBindControl) readonly buffer Control { float control[]; };
layout(std430, binding = kHeightfieldBindCorners) writeonly buffer Corners { float corners[]; };

void basis(float t, out vec4 b, out vec4 db) {
    const float s = 1.0 - t;
    b = vec4(s * s * s, 3.0 * t * t * t - 6.0 * t * t + 4.0, -3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0, t * t * t) / 6.0;
    db = vec4(-s * s / 2.0, (9.0 * t * t - 12.0 * t) / 6.0, (-9.0 * t * t + 6.0 * t + 3.0) / 6.0, t * t / 2.0);
}

vec3 bspline(float x, float y) {
    const int nx = int(P.bspline_nx), ny = int(P.bspline_ny);
    const vec3 lo = holder_min(), hi = holder_max();
    const float dx = (hi.x - lo.x) / float(nx - 1), dy = (hi.y - lo.y) / float(ny - 1);
    const float sx = clamp((x - lo.x) / dx, 0.0, float(nx - 1));
    const float sy = clamp((y - lo.y) / dy, 0.0, float(ny - 1));
    const int i = min(int(sx), nx - 2), j = min(int(sy), ny - 2);
    vec4 bx, dbx, by, dby;
    basis(sx - float(i), bx, dbx);
    basis(sy - float(j), by, dby);
    vec3 r = vec3(0.0);
    for (int m = 0; m < 4; ++m)
        for (int k = 0; k < 4; ++k) {
            const float h = control[clamp(j - 1 + m, 0, ny - 1) * nx + clamp(i - 1 + k, 0, nx - 1)];
            r += h * vec3(by[m] * bx[k], by[m] * dbx[k] / dx, dby[m] * bx[k] / dy);
        }
    return r;
}

vec3 surface(vec2 xy) {
    return kFamily == kFamilyBSpline ? bspline(xy.x, xy.y) : family_height_gradient(xy.x, xy.y);
}

// Invocation p evaluates texel p's centre (where there is one) and its low corner.
void main() {
    const uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x > P.hf_w || p.y > P.hf_h) return;
    const vec3 lo = holder_min(), hi = holder_max();
    const vec2 texel = (hi.xy - lo.xy) / vec2(P.hf_w, P.hf_h);
    corners[p.y * (P.hf_w + 1u) + p.x] = clamp(surface(lo.xy + vec2(p) * texel).x, lo.z, hi.z);
    if (p.x == P.hf_w || p.y == P.hf_h) return;
    const uint index = p.y * P.hf_w + p.x;
    const vec3 zg = surface(lo.xy + (vec2(p) + 0.5) * texel);
    const bool plateau = zg.x <= lo.z || zg.x >= hi.z; // clamped: flat
    heights[index] = clamp(zg.x, lo.z, hi.z);
    gradients[index] = plateau ? vec2(0.0) : zg.yz;
}
