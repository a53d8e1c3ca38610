#version 450
// The paper's z-buffer step (§4.2) as a compute pass: a triangle mesh seen orthographically
// from above, the highest surface kept at each texel centre. A compute pass rather than the
// graphics pipeline because lavapipe at 512 bits (what FIRD asks of it on CPUs with AVX-512,
// docs/architecture.md "CPU vector width") crashes in LLVM compiling any fragment shader.
// Three phases of one pipeline, each a dispatch (MeshRasterPush::phase): the highest height
// over each texel (an atomic max of order keys); the triangle that holds it (the highest
// index among those at that height, so the result does not depend on the order the device
// runs them in); and per texel, the height and that triangle's gradient, clamped to the
// holder as the analytic families are. A tile that one triangle alone reaches skips the
// atomics and the second phase: its texels can be no other's.
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(local_size_x = FIRD_MESH_RASTER_WORKGROUP_SIZE) in;
// Triangle k: corners 3k, 3k+1, 3k+2 (xyz, counter-clockwise seen from above); the
// plane's gradient dz/dx, dz/dy in the first two corners' w.
layout(std430, binding = kMeshRasterBindTriangles) readonly buffer Triangles { vec4 corner[]; };
// (triangle, x0 | y0 << 16, x1 | y1 << 16, sole): the texels [x0, x1) x [y0, y1) of the
// triangle's bounding box in one tile of a kMeshRasterTile-texel grid; sole = 1 where no
// other triangle reaches the tile, whose texels are then the triangle's without atomics.
layout(std430, binding = kMeshRasterBindItems) readonly buffer Items { uvec4 item[]; };
layout(std430, binding = kMeshRasterBindHeightKeys) buffer HeightKeys { uint height_key[]; };
layout(std430, binding = kMeshRasterBindOwners) buffer Owners { uint owner[]; };
layout(std430, binding = kMeshRasterBindHeights) writeonly buffer Heights { float heights[]; };
layout(std430, binding = kMeshRasterBindGradients) writeonly buffer Gradients {
    vec2 gradients[];
};
layout(push_constant) uniform Push { MeshRasterPush pc; };

// A height as an unsigned key in the same order (core Vulkan has no float atomic max): a
// positive float's bits with the sign bit set, a negative one's inverted. 0 stays below
// every height: the mark of a texel no triangle covers.
uint order_key(float z) {
    const uint bits = floatBitsToUint(z);
    return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
}

float key_height(uint key) {
    return uintBitsToFloat((key & 0x80000000u) != 0u ? key & 0x7fffffffu : ~key);
}

// Twice the signed area of (p, q, s): positive where s lies left of p -> q. Evaluated with
// p and q in one fixed order, so that the two triangles sharing an edge compute the same
// value with opposite signs: a texel centre off the edge is covered by exactly one of them
// and none falls through a crack (a rasterizer's watertightness). precise forbids fused
// multiply-adds, which could round the two differently.
float edge(vec2 p, vec2 q, vec2 s) {
    const bool swapped = p.x > q.x || (p.x == q.x && p.y > q.y);
    const vec2 a = swapped ? q : p;
    const vec2 b = swapped ? p : q;
    precise const float e = (b.x - a.x) * (s.y - a.y) - (b.y - a.y) * (s.x - a.x);
    return swapped ? -e : e;
}

void resolve(uint t) {
    if (t >= pc.width * pc.height) return;
    const uint holder = owner[t];
    // A texel no triangle covers (the mesh check forbids them) reads as the floor.
    float z = pc.floor_mm;
    vec2 gradient = vec2(0.0);
    if (holder != 0u) {
        z = key_height(height_key[t]);
        gradient = vec2(corner[3u * (holder - 1u)].w, corner[3u * (holder - 1u) + 1u].w);
    }
    // A clamped height is a plateau: flat.
    const bool plateau = z <= pc.floor_mm || z >= pc.ceiling_mm;
    heights[t] = clamp(z, pc.floor_mm, pc.ceiling_mm);
    gradients[t] = plateau ? vec2(0.0) : gradient;
}

void main() {
    const uint index = gl_GlobalInvocationID.y * pc.row_stride + gl_GlobalInvocationID.x;
    if (pc.phase == kMeshRasterResolve) {
        resolve(index);
        return;
    }
    if (index >= pc.item_count) return;
    const uvec4 it = item[index];
    const bool sole = it.w != 0u;
    if (sole && pc.phase == kMeshRasterOwners) return; // phase 0 wrote its owners
    const vec3 a = corner[3u * it.x].xyz;
    const vec3 b = corner[3u * it.x + 1u].xyz;
    const vec3 c = corner[3u * it.x + 2u].xyz;
    const vec2 lo = vec2(pc.raster_min[0], pc.raster_min[1]);
    const vec2 texel_mm = (vec2(pc.raster_max[0], pc.raster_max[1]) - lo) /
                          vec2(float(pc.width), float(pc.height));
    for (uint y = it.y >> 16; y < (it.z >> 16); ++y) {
        for (uint x = it.y & 0xffffu; x < (it.z & 0xffffu); ++x) {
            precise const vec2 s =
                clamp(lo + (vec2(float(x), float(y)) + 0.5) * texel_mm,
                      vec2(pc.centre_min[0], pc.centre_min[1]),
                      vec2(pc.centre_max[0], pc.centre_max[1]));
            // Barycentric weights (each the area opposite its corner); a centre on an edge
            // counts as inside, and the highest height, then the highest index, wins.
            const float wa = edge(b.xy, c.xy, s);
            const float wb = edge(c.xy, a.xy, s);
            const float wc = edge(a.xy, b.xy, s);
            const float sum = wa + wb + wc;
            if (wa < 0.0 || wb < 0.0 || wc < 0.0 || !(sum > 0.0)) continue;
            precise const float z = (wa * a.z + wb * b.z + wc * c.z) / sum;
            const uint key = order_key(z);
            const uint t = y * pc.width + x;
            if (sole) {
                height_key[t] = key;
                owner[t] = it.x + 1u;
            } else if (pc.phase == kMeshRasterHeights) {
                atomicMax(height_key[t], key);
            } else if (key == height_key[t]) {
                atomicMax(owner[t], it.x + 1u);
            }
        }
    }
}
