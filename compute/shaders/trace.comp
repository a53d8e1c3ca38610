#version 450
// One bounce of the fast path (§4.3): every active ray walks the max-mip quadtree from
// the root, going down where it dips below a node's height and up again after it
// crosses into a neighbour (RQRM, Algorithms 1-4), until it hits a texel or leaves the
// holder box. Hits reflect (material.h: the mirror law and the finish's spread) and are
// appended for the next bounce (ping-pong); rays that leave are binned into the far field
// with integer atomics (rays carry equal energy; with a reflectance below 1, per reflection
// order, which counts_to_lm.comp weighs).
// The traversal state is the level-0 texel and the level: stepping across a face moves
// the texel by exact integer arithmetic, so float rounding cannot make a ray bounce
// between two cells; every loop is bounded by P.max_steps (then counted as aborted).
#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#include "common.glsl"
#include "direction_bucket.glsl"
#include "family.glsl"
#include "material.h"

layout(local_size_x = FIRD_TRACE_WORKGROUP_SIZE) in;
// The rays as texels (FIRD_LOAD_RAY).
layout(binding = kTraceBindRaysIn, rgba32ui) uniform readonly uimageBuffer rays_in;
layout(binding = kTraceBindRaysOut, rgba32ui) uniform writeonly uimageBuffer rays_out;
layout(std430, binding = kTraceBindCounters) buffer Counters { uint counters[]; };
// Texel buffers: CPU drivers read these through a vectorized gather (storage-buffer
// loads at per-lane indices become a bounds-checked scalar loop per lane).
// The quadtree (the walk's one read per step) and the heights (the leaf test's four
// corners) through image buffers: llvmpipe inlines an image load where it calls a function
// around the gather for a texel fetch, and the caller spills its live vectors at each call
// (the quadtree ~3 % of Model C's candidate; the heights ~3 % on an AVX2 CPU,
// docs/architecture.md "On an AVX2 CPU").
layout(binding = kTraceBindPyramid, r32f) uniform readonly imageBuffer pyramid;
layout(binding = kTraceBindHeights, r32f) uniform readonly imageBuffer heights;
layout(binding = kTraceBindGradients) uniform samplerBuffer gradients;
layout(std430, binding = kTraceBindFarField) buffer FarField { uint farfield[]; };
// A ray's record (diagnostics): where it met the surface and the parameter t there (t = -1:
// it met nothing), the reflected direction with the hit texel's index as bits, and the
// slot its reflected ray took in rays_out plus one (0: none), by which a path is followed
// from bounce to bounce.
struct HitRecord {
    vec4 point_t;
    vec4 reflected_texel;
    uvec4 next;
};
layout(std430, binding = kTraceBindHits) writeonly buffer Hits { HitRecord hits[]; };
layout(std430, binding = kTraceBindBuckets) buffer Buckets { uint buckets[]; };
layout(std430, binding = kTraceBindTexelHits) buffer TexelHits { uint texel_hits[]; };
layout(std430, binding = kTraceBindWalk) buffer WalkSteps { vec4 walk[]; };
layout(std430, binding = kTraceBindProfile) buffer Profile { uint profile[]; };
layout(std430, binding = kTraceBindWalkStart) readonly buffer WalkStart { uint walk_start_level; };
// B-spline control heights (hit_gradient), as heightfield.comp reads them.
layout(binding = kTraceBindControl, r32f) uniform readonly imageBuffer control;
layout(std430, binding = kTraceBindLoop) readonly buffer Loop { uint loop_state[]; };
layout(push_constant) uniform Push { TracePush pc; };

// Only in the profiling pipeline (folded away elsewhere): this invocation's walk steps and
// leaf tests, and the steps and leaf tests its subgroup ran as a whole (counted by the
// lane the subgroup elects in each iteration: a lane that waits for the others, between
// two phases of its walk or after it, costs as much as a working one), summed per
// subgroup into 64-bit (low, high) pairs at the end of main.
uint g_steps = 0u;
uint g_leaf_tests = 0u;
uint g_group_steps = 0u;
uint g_group_leaf_tests = 0u;
void profile_add(uint slot, uint n) {
    if (n == 0u) return;
    const uint old = atomicAdd(profile[slot], n);
    if (old + n < old) atomicAdd(profile[slot + 1u], 1u); // carry into the high word
}
void profile_walk() {
    const uint steps = subgroupAdd(g_steps);
    const uint lane_steps = subgroupAdd(g_group_steps) * gl_SubgroupSize;
    const uint leaf_tests = subgroupAdd(g_leaf_tests);
    const uint lane_leaf_tests = subgroupAdd(g_group_leaf_tests) * gl_SubgroupSize;
    const uint rays = subgroupBallotBitCount(subgroupBallot(true));
    if (subgroupElect()) {
        const uint base = pc.bounce * kProfileFields;
        profile_add(base + kProfileRays, rays);
        profile_add(base + kProfileSteps, steps);
        profile_add(base + kProfileLaneSteps, lane_steps);
        profile_add(base + kProfileLeafTests, leaf_tests);
        profile_add(base + kProfileLaneLeafTests, lane_leaf_tests);
    }
}

// Only in the walk-recording pipeline (folded away elsewhere): one step of the picked ray.
// The count is the invocation's own (written out at the end of main), not read back
// from the buffer between steps.
uint g_walk_steps = 0u;
// Each bounce's walk has a region of its own (its count, then its steps).
uint walk_base() { return pc.bounce * (1u + kWalkStepVec4s * kWalkCapacity); }
void record_step(bool picked, int level, ivec2 cell, float h, float t, float t_exit, float z_in,
                 float z_out) {
    if (kRecordWalk == 0u || !picked || g_walk_steps >= kWalkCapacity) return;
    const uint at = walk_base() + 1u + kWalkStepVec4s * g_walk_steps;
    walk[at] = vec4(float(level), vec2(cell), h);
    walk[at + 1u] = vec4(t, t_exit, z_in, z_out);
    walk[at + 2u] = vec4(float(kWalkUndecided), t, 0.0, 0.0);
    ++g_walk_steps;
}
// What the last recorded step decided, and the t it moves the ray to.
void record_decision(bool picked, uint decision, float t_next) {
    if (kRecordWalk == 0u || !picked || g_walk_steps == 0u || g_walk_steps > kWalkCapacity) return;
    walk[walk_base() + 1u + kWalkStepVec4s * (g_walk_steps - 1u) + 2u] = vec4(float(decision), t_next, 0.0, 0.0);
}

const int kMiss = 0;
const int kHit = 1;
const int kAborted = 2;
const int kBlocked = 3; // entered the box through a side face below the surface

// The paper mode's texel height (its quadtree's level 0).
float height_at(ivec2 t) {
    t = clamp(t, ivec2(0), ivec2(P.hf_w - 1u, P.hf_h - 1u));
    return imageLoad(heights, int(uint(t.y) * P.hf_w + uint(t.x))).r;
}
vec2 gradient_at(ivec2 t) {
    t = clamp(t, ivec2(0), ivec2(P.hf_w - 1u, P.hf_h - 1u));
    return texelFetch(gradients, int(uint(t.y) * P.hf_w + uint(t.x))).rg;
}

// The refined mode's surface over texel `cell`: the bilinear patch through the heights at
// its four corners, (x0y0, x1y0, x0y1, x1y1) (heightfield.comp samples the corners).
vec4 patch_corners(ivec2 cell) {
    const uint row = P.hf_w + 1u;
    const int c = int(uint(cell.y) * row + uint(cell.x));
    return vec4(imageLoad(heights, c).r, imageLoad(heights, c + 1).r,
                imageLoad(heights, c + int(row)).r, imageLoad(heights, c + int(row) + 1).r);
}

// Bilinear interpolation at texel-space q over the patch of texel `cell` with corners c.
float bilinear(vec2 q, ivec2 cell, vec4 c) {
    const vec2 f = q - vec2(cell);
    return mix(mix(c.x, c.y, f.x), mix(c.z, c.w, f.x), f.y);
}

// The refined mode's surface height at texel-space q (the texel under it, clamped to the
// texture).
float surface_height(vec2 q) {
    const ivec2 cell = clamp(ivec2(floor(q)), ivec2(0), ivec2(P.hf_w - 1u, P.hf_h - 1u));
    return bilinear(q, cell, patch_corners(cell));
}

// The gradient (dz/dx, dz/dy) of the bilinear patch of texel `cell` at texel-space q.
vec2 patch_gradient(vec2 q, ivec2 cell, vec2 texel_mm) {
    const vec4 c = patch_corners(cell);
    const vec2 f = q - vec2(cell);
    return vec2(mix(c.y - c.x, c.w - c.z, f.y), mix(c.z - c.x, c.w - c.y, f.x)) / texel_mm;
}

float control_height(int k) { return imageLoad(control, k).r; }

// The gradient the refined mode reflects about at hit point p (texel-space q, texel
// `cell`): the surface actually hit. An analytic family's own gradient there (zero where
// the holder clamps it, as model/surface.cpp's clamped surface); for a mesh, the face
// gradient rasterized at the hit texel's centre (a facet's plane, never a blend of two).
vec2 hit_gradient(vec3 p, ivec2 cell) {
    if (kFamily == kFamilyTexture) return gradient_at(cell);
    const vec3 zg = reflector_height_gradient(p.xy);
    const vec3 lo = holder_min(), hi = holder_max();
    return (zg.x <= lo.z || zg.x >= hi.z) ? vec2(0.0) : zg.yz;
}

// The walk's minimum and maximum of two finite values (t, z, a root's parameter): CPU
// drivers lower GLSL's min and max to a NaN-aware sequence, in two halves at 512 bits,
// where a compare and a select is an instruction each. (A NaN operand gives the second.)
float min_walk(float a, float b) { return a < b ? a : b; }
float max_walk(float a, float b) { return a > b ? a : b; }

struct Walk {
    vec3 o;     // origin (mm)
    vec3 d;     // direction
    vec2 O;     // origin in texel units
    vec2 D;     // direction in texel units per mm of t
};

vec2 texel_pos(Walk w, float t) { return w.O + t * w.D; }

// The texel under texel-space point q, never behind `current` along the direction of
// travel: beyond 2048 texels a float's ulp (2.4e-4 texel) exceeds any small bias, and a
// position re-derived at a face just crossed could otherwise put the ray back across it
// (and cycle between a cell and its parent).
// `forward` is per axis whether the ray moves towards higher texels (either value serves
// where it does not move along the axis: the position never changes there, so the texel
// under q is the current one, or one past the texture's last, which the walk clamps back),
// so a step picks the larger or smaller texel with no branch (and no multiplication) on
// the direction.
ivec2 texel_ahead(vec2 q, ivec2 current, bvec2 forward) {
    const ivec2 under = ivec2(floor(q));
    return mix(min(under, current), max(under, current), forward);
}

// The first root of the ray against the bilinear patch over texel `cell` within
// [a, b] past t_ignore where the ray crosses the patch from above to below, as a t;
// returns -1 when there is none. Along the ray the patch's height is quadratic in t, so
// the gap g(t) = ray z - patch z is the quadratic through its values at a, the middle
// and b. A root where g rises (the ray leaving the solid: a reflected ray at its own
// start, or a ray already below) is never a hit.
float refine_in_texel(Walk w, ivec2 cell, float a, float b, float t_ignore) {
    if (b <= t_ignore) return -1.0;
    const vec4 c = patch_corners(cell);
    const float g0 = w.o.z + a * w.d.z - bilinear(texel_pos(w, a), cell, c);
    const float gm = w.o.z + 0.5 * (a + b) * w.d.z - bilinear(texel_pos(w, 0.5 * (a + b)), cell, c);
    float g1 = w.o.z + b * w.d.z - bilinear(texel_pos(w, b), cell, c);
    // The holder's floor is solid (the surface is clamped to it, never below): a ray
    // that reaches it in this texel has met the surface, whatever rounding says of the
    // gap there (a plateau on the floor, such as the fluted cup's apex).
    if (w.o.z + b * w.d.z <= P.holder_min[2] + P.offset_mm) g1 = min_walk(g1, 0.0);
    // Entering the texel below its patch: the crossing from above lay on the face just
    // crossed (the patches share their edges, so only rounding hides it in the texel
    // before); the hit is there. Not within the ignore window of a reflected ray's start.
    if (g0 <= 0.0 && a > t_ignore) return a;
    // g(s) = qa s^2 + qb s + qc on s in [0, 1]: the root past smin where g falls.
    const float qa = 2.0 * (g0 - 2.0 * gm + g1);
    const float qb = g1 - g0 - qa;
    const float qc = g0;
    const float smin = t_ignore > a ? (t_ignore - a) / (b - a) : 0.0;
    float s = 2.0;
    if (abs(qa) < 1e-12 * (abs(qb) + abs(qc) + 1e-30)) {
        if (qb < 0.0) s = -qc / qb; // linear, falling
    } else {
        const float disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            const float root = sqrt(disc);
            const float q = -0.5 * (qb + (qb >= 0.0 ? root : -root));
            float s1 = q / qa;
            float s2 = q != 0.0 ? qc / q : s1;
            if (s1 > s2) { const float tmp = s1; s1 = s2; s2 = tmp; }
            // g'(s1) = qa (s1 - s2) and g'(s2) = qa (s2 - s1): g falls through the
            // smaller root when qa > 0 and through the larger one when qa < 0.
            s = qa > 0.0 ? s1 : s2;
        }
    }
    if (s < smin || s > 1.0) {
        // From above at a to at-or-below at b, there is a falling crossing in between
        // even where rounding put the quadratic's root past b (or found none): a ray
        // meeting a plateau that lies on the holder's floor ends its segment on it.
        if (!(g0 > 0.0 && g1 <= 0.0 && smin <= 0.0)) return -1.0;
        s = s <= 1.0 ? max_walk(s, 0.0) : 1.0;
    }
    return a + min_walk(max_walk(s, 0.0), 1.0) * (b - a);
}

// Steps per round of a reflected ray's walk (see rqrm's loop).
const uint kWalkRoundSteps = 8u;

// RQRM: returns kHit with t_hit and the hit texel, kMiss, kAborted or kBlocked.
// `start_level`: walk_start.comp's level (read by main where every lane is active).
int rqrm(Walk w, float t_start, ivec2 skip_texel, bool picked, uint start_level, out float t_hit,
         out ivec2 hit_texel) {
    t_hit = 0.0;
    hit_texel = ivec2(0);
    vec2 t01;
    if (!clip_to_box(w.o, w.d, holder_min(), holder_max(), t01)) return kMiss;
    float t = max(t01.x, t_start);
    const int top = int(P.levels) - 1;
    // Nothing stands above the quadtree root's height (the reflector's highest point): a
    // rising ray that passes it leaves through the holder's open top without a hit, so
    // its walk ends there rather than climbing the quadtree to the holder's top face.
    float t_end = t01.y;
    if (w.d.z > 0.0 && pc.walk_to_box_top == 0u)
        t_end = min(t_end, (imageLoad(pyramid, int(P.level_offset[top])).r - w.o.z) / w.d.z);
    if (t >= t_end) return kMiss;
    const ivec2 size = ivec2(P.hf_w, P.hf_h);
    const vec2 bias = sign(w.D) * 1e-4; // choose cells in the direction of travel
    ivec2 texel = clamp(ivec2(floor(texel_pos(w, t) + bias)), ivec2(0), size - 1);

    // Entering through a side face below the surface meets the back of the reflector.
    if (t01.x > t_start) {
        const float z = w.o.z + t * w.d.z;
        const bool top_face = abs(z - P.holder_max[2]) <= 1e-5 * (1.0 + abs(P.holder_max[2]));
        const float surface = kHitMode == kHitModePaper ? height_at(texel) : surface_height(texel_pos(w, t));
        if (!top_face && z < surface) return kBlocked;
    }

    // A ray leaving the surface after a reflection lies under every node above its texel,
    // so a walk from the root would only descend to that texel: start there instead.
    // A ray from the source that starts inside the source's bounding box lies under
    // every node down to walk_start.comp's level: its walk starts there.
    const bool from_surface = kBounceKind == kBounceReflected ||
                              (kBounceKind == kBounceEither && skip_texel.x >= 0);
    const vec3 start = w.o + t * w.d;
    const bool at_source = !from_surface && pc.walk_from_root == 0u &&
                           all(greaterThanEqual(start, vec3(P.source_box_min[0], P.source_box_min[1], P.source_box_min[2]))) &&
                           all(lessThanEqual(start, vec3(P.source_box_max[0], P.source_box_max[1], P.source_box_max[2])));
    const uint s = start_level;
    int level = from_surface ? 0 : (at_source ? int(s) : top);
    // The node's row in the quadtree buffer follows the level by integer arithmetic
    // (level l is ceil(W / 2^l) x ceil(H / 2^l) nodes, stored after the finer levels):
    // indexing the parameter tables by a per-ray level costs a gather on CPU drivers (so
    // both candidates are read at indices common to all rays, then one is chosen).
    uint level_offset = from_surface ? 0u : (at_source ? P.level_offset[s] : P.level_offset[top]);
    uint level_w = from_surface ? P.hf_w : (at_source ? P.level_w[s] : P.level_w[top]);
    // CPU drivers (lavapipe) run both sides of every branch under a lane mask, so the
    // inner loop holds only the walk: it stops at a candidate texel (level 0, the ray
    // dips below its height) and the leaf test runs outside it, once per candidate.
    // Algorithm 3's node bounds, set up once per ray so that a step has no branch on the
    // direction: the ray leaves a node through its far face on each axis it moves along
    // (far_side 1: the high face), at t = (face - O) / D with a reciprocal (a division
    // per lane is slow on CPUs); an axis it does not move along never ends a node (its
    // origin is put 1e30 texels behind, so that face's t is ~1e30, past any t_end).
    // (A subnormal heading counts as none: its reciprocal would be infinite, and 0 * inf a
    // NaN t at a face through the origin.)
    const bvec2 moves = greaterThanEqual(abs(w.D), vec2(1.17549435e-38));
    const bvec2 toward_high = greaterThan(w.D, vec2(0.0));
    const ivec2 far_side = ivec2(toward_high);
    const vec2 inv_D = vec2(moves.x ? 1.0 / w.D.x : 1.0, moves.y ? 1.0 / w.D.y : 1.0);
    const vec2 face_origin = vec2(moves.x ? w.O.x : -1e30, moves.y ? w.O.y : -1e30);
    const float inv_dz = w.d.z != 0.0 ? 1.0 / w.d.z : 0.0;
    const bool descending = w.d.z < 0.0;
    bool across = false; // the candidate was not a hit: leave the texel
    uint step = 0u;
    // Read once, before the loops (a storage buffer's value was loaded lane by lane, masked,
    // at every round; the scene's parameters are a uniform buffer now: common.glsl).
    const uint max_steps = P.max_steps;
    while (step < max_steps) {
        bool candidate = false;
        float cand_t_exit = t;
        // A subgroup runs the leaf test when every lane has stopped at a candidate or
        // ended its walk, so a lane at a candidate waits for the others' walks. Reflected
        // rays stop at many candidates without a root (without rounds, lane utilization
        // 0.39-0.46 in Model C's bounces 1-2, where each lane's walk alone would fill
        // 0.71-0.81): their walk runs in rounds of kWalkRoundSteps steps, after each of
        // which the leaf test runs for the lanes at a candidate and the others walk on
        // (docs/architecture.md, "Walk rounds"). A source's rays, with ~1 leaf test each,
        // walk in one round: a round's end costs a leaf test run by every lane, masked.
        // Every lane's walk is the same step for step; only the leaf tests' timing among
        // lanes moves.
        const uint round_end = from_surface ? step + min(kWalkRoundSteps, max_steps - step) : max_steps;
        for (; step < round_end; ++step) {
            const ivec2 cell = texel >> level;
            const vec2 face = vec2(min((cell + far_side) << level, size));
            const vec2 t_faces = (face - face_origin) * inv_D;
            const float tx = t_faces.x, ty = t_faces.y;
            const float t_exit = min_walk(min_walk(tx, ty), t_end);
            const float h = imageLoad(pyramid, int(level_offset + uint(cell.y) * level_w + uint(cell.x))).r;
            const float z_in = w.o.z + t * w.d.z;
            const float z_out = w.o.z + max_walk(t_exit, t) * w.d.z;
            record_step(picked, level, cell, h, t, t_exit, z_in, z_out);
            if (kProfile != 0u) {
                ++g_steps;
                if (subgroupElect()) ++g_group_steps;
            }
            // The ray's lowest point in the node: z is monotonic in t (rounding included).
            const bool below = !across && (descending ? z_out : z_in) <= h;
            across = false;
            if (below && level == 0) {
                candidate = true;
                cand_t_exit = max_walk(t_exit, t);
                ++step;
                break;
            }
            // One position update serves both moves (CPU drivers run both branches):
            // Algorithm 4 lines 1-6, the ray reaches the node's height inside the node:
            // advance to that height and go down one level; lines 11-13, no hit under
            // this node: move to the neighbour across the face the ray leaves through,
            // then go up a level.
            if (!below && t_exit >= t_end) {
                record_decision(picked, kWalkLeave, t_exit);
                return kMiss;
            }
            const float t_descend = (descending && z_in > h) ? max_walk(t, (h - w.o.z) * inv_dz) : t;
            t = below ? t_descend : t_exit;
            record_decision(picked, below ? kWalkDescend : kWalkAdvance, t);
            const ivec2 ahead = texel_ahead(texel_pos(w, t) + bias, texel, toward_high);
            if (below) {
                --level;
                const uint round_up = (1u << level) - 1u;
                level_w = (P.hf_w + round_up) >> level;
                level_offset -= level_w * ((P.hf_h + round_up) >> level);
                const ivec2 span = ivec2(1 << level);
                const ivec2 child_lo = cell << 1;
                const ivec2 child = clamp(ahead >> level, child_lo, child_lo + 1);
                // Keep the texel inside the child cell (and inside the texture).
                texel = clamp(ahead, child * span, min((child + 1) * span, size) - 1);
            } else {
                const ivec2 cell_lo = cell << level;
                const ivec2 cell_hi = min((cell + 1) << level, size) - 1;
                ivec2 next = clamp(ahead, cell_lo, cell_hi);
                // Across the face(s) it leaves through (a corner: both).
                const ivec2 across_face = mix(cell_lo - 1, cell_hi + 1, toward_high);
                next = mix(next, across_face, bvec2(tx <= ty, ty <= tx));
                if (any(lessThan(next, ivec2(0))) || any(greaterThanEqual(next, size))) {
                    record_decision(picked, kWalkLeave, t);
                    return kMiss;
                }
                texel = next;
                // Up a level only into a new parent: a face inside the parent leads to a
                // sibling, and the parent would only send the ray down to it again.
                if (level < top && any(notEqual(next >> (level + 1), cell >> 1))) {
                    record_decision(picked, kWalkAscend, t);
                    const uint round_up = (1u << level) - 1u;
                    level_offset += level_w * ((P.hf_h + round_up) >> level);
                    level_w = (level_w + 1u) >> 1;
                    ++level;
                }
            }
        }
        if (!candidate) continue; // the round ended: walk on (past the step limit: aborted)
        if (kProfile != 0u) {
            ++g_leaf_tests;
            if (subgroupElect()) ++g_group_leaf_tests;
        }
        // Algorithm 1 lines 13-15 (paper) or the refined surface.
        if (kHitMode == kHitModePaper) {
            if (texel != skip_texel) { // not the texel the ray reflected from
                const float h = imageLoad(heights, int(uint(texel.y) * P.hf_w + uint(texel.x))).r;
                const float z_in = w.o.z + t * w.d.z;
                t_hit = (w.d.z < 0.0 && z_in > h) ? max(t, (h - w.o.z) / w.d.z) : t;
                hit_texel = texel;
                record_decision(picked, kWalkHit, t_hit);
                return kHit;
            }
            record_decision(picked, kWalkOwnTexel, t);
        } else {
            // A reflected ray ignores roots within the offset of its start in every texel
            // (a hit on a texel edge whose reflection heads into the neighbour too).
            const float t_ignore = from_surface ? t_start : -1.0;
            const float th = refine_in_texel(w, texel, t, cand_t_exit, t_ignore);
            if (th >= 0.0) {
                t_hit = th;
                hit_texel = texel;
                record_decision(picked, kWalkHit, t_hit);
                return kHit;
            }
            record_decision(picked, kWalkNoRoot, t);
        }
        across = true;
    }
    return kAborted;
}

uint far_field_cell(vec3 d) {
    // atan(0, 0) is undefined in GLSL: a ray straight up or down takes the column of
    // phi = 0, as DESIGN.md §2's atan2 (and farfield_cell on the CPU) gives.
    const float phi = (d.x == 0.0 && d.y == 0.0) ? 0.0 : atan(d.y, d.x);
    // Not asin(d.z): Mesa lowers asin to a polynomial whose error (~1e-4 rad near the
    // poles) moved 0.75 % of a flat mirror's rays one row off the reference's; atan is
    // accurate to float rounding there (tests/app: BenchSameRaysErrorIsTheDiscretizationAlone).
    const float theta = atan(d.z, length(d.xy));
    const int col = clamp(int(floor((phi + kPi) / (2.0 * kPi) * float(P.ff_w))), 0, int(P.ff_w) - 1);
    const int row = clamp(int(floor((0.5 * kPi - theta) / kPi * float(P.ff_h))), 0, int(P.ff_h) - 1);
    return uint(row) * P.ff_w + uint(col);
}

// The hit records and texel-hit counts (tests, paths, exports) are only in the
// diagnostics pipeline (kDiagnostics): CPU drivers run a branch's masked stores and
// atomics even when a push constant turns it off for every lane.
void main() {
    const uint i = gl_GlobalInvocationID.x;
    // Buffer values the same for every invocation are read before the first branch: CPU
    // drivers load a storage buffer in divergent control flow lane by lane.
    const uint active_rays = loop_state[kLoopActive];
    const uint start_level = walk_start_level;
    if (i >= active_rays) return;
    const bool order_output = pc.order_output != 0u && active_rays >= kOrderMinRays;
    const Ray ray = FIRD_LOAD_RAY(rays_in, i);
    // The picked ray: by the emission index it carries (its slot changes from bounce to bounce).
    const bool picked = kRecordWalk != 0u && floatBitsToUint(ray.origin.w) == pc.walk_ray;
    const uint record = pc.hits_base + i;
    if (kDiagnostics != 0u && pc.record_hits != 0u) {
        hits[record].point_t = vec4(0.0, 0.0, 0.0, -1.0);
        hits[record].reflected_texel = vec4(0.0);
        hits[record].next = uvec4(0u);
    }
    const vec3 lo = holder_min(), hi = holder_max();
    const vec2 texel_mm = (hi.xy - lo.xy) / vec2(P.hf_w, P.hf_h);
    Walk w;
    w.o = ray.origin.xyz;
    w.d = ray.direction.xyz;
    w.O = (w.o.xy - lo.xy) / texel_mm;
    w.D = w.d.xy / texel_mm;

    // Every lane with a ray reaches the counting at the end (no early returns past the
    // one above, for invocations beyond the active rays), so the counters are aggregated
    // per subgroup.
    bool below = false, aborted = false, blocked = false, direct = false;
    bool far_miss = false, far_final = false, lost_again = false, append = false;
    vec3 far_dir = w.d;
    Ray next;
    next.origin = vec4(0.0);
    next.direction = vec4(0.0);

    ivec2 skip = ivec2(-1);
    float t_start = 0.0;
    // The source's rays and reflected ones are traced by pipelines of their own
    // (kBounceKind): CPU drivers would run this test of the source's, masked, in every bounce.
    const bool reflected = kBounceKind == kBounceReflected || (kBounceKind == kBounceEither && pc.bounce > 0u);
    if (reflected) {
        const uint texel_bits = floatBitsToUint(ray.direction.w); // the texel it reflected from
        skip = ivec2(texel_bits & 0xFFFFu, texel_bits >> 16u);
        t_start = P.offset_mm; // Algorithm 2 line 7: a small initial offset after a reflection
    } else if (all(greaterThanEqual(w.O, vec2(0.0))) && all(lessThan(w.O, vec2(P.hf_w, P.hf_h))) &&
               w.o.z < (kHitMode == kHitModePaper ? height_at(ivec2(floor(w.O))) : surface_height(w.O))) {
        // The source is inside the reflector (against the surface the hit mode traces:
        // a texel's column, or the bilinear surface, which a steep wall's column
        // overshoots by up to half a texel's rise).
        below = true;
    }
    if (!below) {
        float t_hit;
        ivec2 hit_texel;
        const int result = rqrm(w, t_start, skip, picked, start_level, t_hit, hit_texel);
        aborted = result == kAborted;
        blocked = result == kBlocked;
        if (result == kMiss) {
            direct = !reflected;
            far_miss = !direct;
        } else if (result == kHit) {
            if (pc.final_check != 0u) {
                lost_again = true; // strict policy: it would hit again
            } else {
                vec3 p = w.o + t_hit * w.d;
                const vec3 p_hit = p; // where the ray meets the surface (before the paper lift)
                const vec2 q = texel_pos(w, t_hit);
                const vec2 g = kHitMode == kHitModePaper ? gradient_at(hit_texel) : hit_gradient(p, hit_texel);
                const vec3 n = normalize(vec3(-g, 1.0));
                vec2 u = vec2(0.5);
                // A mirror (kSpread 0) folds the draw and the spread away: CPU drivers would
                // run them for every reflection, masked, on the value of P.spread_rad alone.
                const float spread_rad = kSpread != 0u ? P.spread_rad : 0.0;
                if (kSpread != 0u) { // this reflection's draw: (ray index, bounce) alone
                    const uint index_lo = floatBitsToUint(ray.origin.w);
                    const uint index_hi = pc.first_hi + (index_lo < pc.first_lo ? 1u : 0u);
                    u = to_unit(philox(uvec4(index_lo, index_hi, kMaterialStream + pc.bounce, 0u),
                                       uvec2(P.seed_lo, P.seed_hi)).xy);
                }
                vec3 r = reflected_direction(w.d, n, spread_rad, P.spread_lobe, u.x, u.y);
                if (kHitMode != kHitModePaper) {
                    // Never into the surface traced: where the true normal and the patch
                    // hit part (within a texel of a kink), reflect about the patch itself,
                    // which the ray met from above (d . n_patch < 0, so r . n_patch > 0).
                    const vec3 n_patch = normalize(vec3(-patch_gradient(q, hit_texel, texel_mm), 1.0));
                    if (dot(r, n_patch) <= 0.0) r = mirror_direction(w.d, n_patch);
                }
                if (kHitMode == kHitModePaper) p.z = max(p.z, height_at(hit_texel)); // on the texel top
                const uint texel = uint(hit_texel.y) * P.hf_w + uint(hit_texel.x);
                if (kDiagnostics != 0u && pc.record_hits != 0u) {
                    hits[record].point_t = vec4(p_hit, t_hit);
                    hits[record].reflected_texel = vec4(r, uintBitsToFloat(texel));
                }
                if (kDiagnostics != 0u && pc.count_texel_hits != 0u) {
                    atomicAdd(texel_hits[texel], 1u);
                    if (pc.bounce == 0u) atomicAdd(texel_hits[P.hf_w * P.hf_h + texel], 1u);
                }
                if (pc.bounce + 1u == P.max_bounces && kStrictPolicy == 0u) {
                    far_final = true; // "paper": leave with the last reflected direction
                    far_dir = r;
                } else {
                    append = true;
                    // origin.w keeps the ray's emission index; direction.w packs the texel.
                    next.origin = vec4(p, ray.origin.w);
                    next.direction = vec4(r, uintBitsToFloat(uint(hit_texel.x) | (uint(hit_texel.y) << 16u)));
                }
            }
        }
    }
    if (picked) walk[walk_base()] = vec4(float(g_walk_steps), 0.0, 0.0, 0.0);
    if (kProfile != 0u) profile_walk();
    // Layer k of the far field holds the rays that left after k reflections (one layer when
    // every ray weighs the same); direct light is layer 0, binned where the scene asks.
    const bool binned = far_miss || far_final || (direct && P.bin_direct != 0u);
    if (binned) {
        const uint reflections = far_final ? pc.bounce + 1u : pc.bounce;
        const uint layer = P.farfield_layers > 1u ? reflections : 0u;
        atomicAdd(farfield[layer * P.ff_w * P.ff_h + far_field_cell(far_dir)], 1u);
    }
    // The bounce's tally: every counter this ray adds to, 8 bits each (a subgroup has at
    // most 128 lanes), summed over the subgroup in one reduction and added by one lane.
    // (CPU drivers run a subgroup operation or an atomic as a loop over the lanes: one
    // reduction in place of a ballot and an election per counter.)
    const bool lost = below || aborted || blocked || lost_again;
    const uvec2 tally = subgroupAdd(uvec2(uint(below) | (uint(aborted) << 8u) | (uint(lost) << 16u) |
                                              (uint(direct) << 24u),
                                          uint(far_miss) | (uint(far_final) << 8u)));
    if (subgroupElect()) {
        const uint copy = (gl_WorkGroupID.x % kTallyCopies) * kCounterCount;
        const uint n_below = tally.x & 0xFFu, n_aborted = (tally.x >> 8u) & 0xFFu;
        const uint n_lost = (tally.x >> 16u) & 0xFFu, n_direct = tally.x >> 24u;
        const uint n_far_miss = tally.y & 0xFFu, n_far_final = tally.y >> 8u;
        if (n_below > 0u) atomicAdd(counters[copy + kCounterBelow], n_below);
        if (n_aborted > 0u) atomicAdd(counters[copy + kCounterAborted], n_aborted);
        if (n_lost > 0u) {
            atomicAdd(counters[copy + kCounterLost], n_lost);
            atomicAdd(counters[copy + kCounterLostByReflections + pc.bounce], n_lost);
        }
        if (n_direct > 0u) atomicAdd(counters[copy + kCounterDirect], n_direct);
        if (n_far_miss + n_far_final > 0u) atomicAdd(counters[copy + kCounterFarField], n_far_miss + n_far_final);
        if (n_far_miss > 0u) atomicAdd(counters[copy + kCounterByReflections + pc.bounce], n_far_miss);
        if (n_far_final > 0u) atomicAdd(counters[copy + kCounterByReflections + pc.bounce + 1u], n_far_final);
    }
    uint slot;
    FIRD_APPEND_INDEX(counters, kCounterActiveOut, append, slot);
    if (append) {
        FIRD_STORE_RAY(rays_out, slot, next);
        if (kDiagnostics != 0u && pc.record_hits != 0u) hits[record].next.x = slot + 1u;
        // Counted for ordering the next bounce's rays by direction (rayset_order.comp).
        if (order_output) atomicAdd(buckets[reflected_bucket(next.origin.xyz, next.direction.xyz)], 1u);
    }
}
