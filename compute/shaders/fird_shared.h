// Constants and push-constant structs read by both C++ and GLSL: workgroup sizes,
// binding numbers and push-constant layouts are defined once, here.
// Push-constant structs use only 4-byte scalars so std430 and C++ layouts agree.
#ifndef FIRD_SHARED_H
#define FIRD_SHARED_H

#ifdef __cplusplus
#include <cstdint>
namespace fird::gpu {
using uint = std::uint32_t;
#define FIRD_CONSTANT(type, name, value) inline constexpr type name = value
#define FIRD_FUNCTION constexpr
#else
#define FIRD_CONSTANT(type, name, value) const type name = value
#define FIRD_FUNCTION
#endif

// Workgroup sizes are macros so GLSL layout qualifiers and C++ dispatch math share them.
#define FIRD_REDUCE_WORKGROUP_SIZE 256
#define FIRD_BIN_KEYS_WORKGROUP_SIZE 256

// ---- reduce_sum.comp: sum of x, or of (a - b)^2 (the l2 distance's sum) ----
FIRD_CONSTANT(uint, kReduceWorkgroupSize, FIRD_REDUCE_WORKGROUP_SIZE);
FIRD_CONSTANT(uint, kReduceItemsPerThread, 8u);
// The inputs are R32_SFLOAT texel views (passes/float_table.hpp); the partials a buffer.
FIRD_CONSTANT(uint, kReduceBindingA, 0u);       // float[a_offset + count]
FIRD_CONSTANT(uint, kReduceBindingB, 1u);       // float[count] (mode kReduceSquaredDifference)
FIRD_CONSTANT(uint, kReduceBindingPartial, 2u); // float[groups]
// float[height]: each row's metric weight, computed on the host in double (mode
// kReduceCandelaSquaredDifference; a shader's sin and cos may be as coarse as 2^-11 by
// Vulkan's precision rules, and are on some drivers, which the polar cells' weights do not
// survive).
FIRD_CONSTANT(uint, kReduceBindingRowWeight, 3u);
FIRD_CONSTANT(uint, kReduceSum, 0u);
FIRD_CONSTANT(uint, kReduceSquaredDifference, 1u);
// (a - b)^2 / (4 pi omega), omega the cell's solid angle (farfield.hpp's candela_l2)
FIRD_CONSTANT(uint, kReduceCandelaSquaredDifference, 2u);
// The mode is a specialization constant (one pipeline per mode): CPU drivers run every
// side of a branch, and the candela mode's row of each cell costs a division per lane.
#define FIRD_SPEC_REDUCE_MODE 0
struct ReducePush {
    uint count;
    uint width; // kReduceCandelaSquaredDifference: the far field's grid
    uint height;
    uint a_offset; // where the level's inputs begin in a (a level past the first: the scratch)
};

// ---- bin_keys.comp: atomic histogram of integer keys ----
FIRD_CONSTANT(uint, kBinKeysWorkgroupSize, FIRD_BIN_KEYS_WORKGROUP_SIZE);
FIRD_CONSTANT(uint, kBinKeysBindingKeys, 0u); // uint[count]
FIRD_CONSTANT(uint, kBinKeysBindingBins,
              1u); // uint[bin_count + 1]; last slot counts out-of-range keys
struct BinKeysPush {
    uint count;
    uint bin_count;
};

// ---- the fast path: rayset.comp, heightfield.comp, maxmip.comp, trace.comp ----
#define FIRD_RAYSET_WORKGROUP_SIZE 128
#define FIRD_TRACE_WORKGROUP_SIZE 64
#define FIRD_HEIGHTFIELD_WORKGROUP_SIZE 16 // 16 x 16 texels
#define FIRD_MAX_LEVELS 16                 // quadtree levels: textures up to 32768 texels wide
#define FIRD_MAX_PARAMS 8
#define FIRD_MAX_REFLECTIONS 64

FIRD_CONSTANT(uint, kFamilyPlane, 0u);
FIRD_CONSTANT(uint, kFamilyParaboloid, 1u);
FIRD_CONSTANT(uint, kFamilyCup, 2u);
FIRD_CONSTANT(uint, kFamilyFlutedCup, 3u);
FIRD_CONSTANT(uint, kFamilyBSpline, 4u);
FIRD_CONSTANT(uint, kFamilyTexture, 5u); // heights rasterized from a triangle mesh
FIRD_CONSTANT(uint, kFamilyProfile, 6u); // params (z0, cx, cy, spacing), bspline_nx heights

// The finish's spread lobe (material.h) and its random stream: the counter (ray index,
// kMaterialStream + bounce) under the seed, so a reflection's draw depends on the ray and
// the bounce alone (not on the batch or the order the rays are traced in).
FIRD_CONSTANT(uint, kLobeGaussian, 0u);
FIRD_CONSTANT(uint, kLobePhong, 1u);
FIRD_CONSTANT(uint, kMaterialStream, 256u);

FIRD_CONSTANT(uint, kSourceCylinder, 0u);
FIRD_CONSTANT(uint, kSourceSphere, 1u);
FIRD_CONSTANT(uint, kSourcePointIsotropic, 2u);
FIRD_CONSTANT(uint, kSourcePointCosine, 3u);
FIRD_CONSTANT(uint, kSourceDisk, 4u);        // one-sided Lambertian disk (an LED die)
FIRD_CONSTANT(uint, kSourceRectangle, 5u);   // one-sided Lambertian rectangle (a COB)
FIRD_CONSTANT(uint, kSourcePhotometric, 6u); // an IES / LDT distribution (emitter.h's table)
// A measured ray file: the host reads the batch's rays into the emitter table buffer (six
// floats each: origin, direction, in the scene's frame) and rayset.comp takes ray i of it.
FIRD_CONSTANT(uint, kSourceRayFile, 7u);
FIRD_CONSTANT(uint, kRayFileFloats, 6u);

FIRD_CONSTANT(uint, kSamplerRandom, 0u); // independent Philox rays
FIRD_CONSTANT(uint, kSamplerSobol, 1u);
FIRD_CONSTANT(uint, kSamplerStratified, 2u); // Philox, stratified in its first two dimensions
// The stratified sampler's strata: a 2^bits x 2^bits grid over its first two uniforms,
// visited along a Morton curve as the ray index grows (sampling/strata.hpp, common.glsl).
FIRD_CONSTANT(uint, kStratumBits, 8u);
FIRD_CONSTANT(uint, kStrataBits, 2u * kStratumBits); // bits of a stratum's Morton index
FIRD_CONSTANT(uint, kStrata, 1u << kStrataBits);
// A stratified uniform is cell, offset inside it and a half bit: 23 bits and a half, exact
// in float.
FIRD_CONSTANT(uint, kStratumOffsetBits, 23u - kStratumBits);

// A sphere's, a cylinder's, a point's, a disk's or a rectangle's direction is a continuous
// function of the first two uniforms alone (emitter.h), so with the stratified sampler its
// rayset is emitted already ordered by direction: rayset.comp writes it in place and no
// sort follows. A photometric source's cells come in C-major order (a turn of gamma per
// C), a ray file's rays come in the file's order, and the other samplers' rays come in no
// order: those raysets are sorted.
FIRD_FUNCTION bool rayset_ordered_at_birth(uint sampler_kind, uint source_kind) {
    return sampler_kind == kSamplerStratified && source_kind != kSourcePhotometric &&
           source_kind != kSourceRayFile;
}

FIRD_CONSTANT(uint, kHitModePaper, 0u);
FIRD_CONSTANT(uint, kHitModeRefined, 1u);
// The rays of the bounces a trace pipeline runs (FIRD_SPEC_BOUNCE_KIND): the source's
// (bounce 0) or reflected ones (the bounces after) in the two pipelines of a plain run,
// which fold away the other's tests (the source inside the reflector, the walk's start
// below the source); either, by the bounce's number, in the diagnostics' variants.
FIRD_CONSTANT(uint, kBounceEither, 0u);
FIRD_CONSTANT(uint, kBounceFromSource, 1u);
FIRD_CONSTANT(uint, kBounceReflected, 2u);

// Specialization constant ids: what a scene fixes for the life of its pipelines. The
// shaders branch on these, not on SceneParams' copies, so the driver folds the branches
// away (CPU drivers such as lavapipe otherwise run every side of a branch, masked).
#define FIRD_SPEC_SOURCE_KIND 0
#define FIRD_SPEC_SAMPLER_KIND 1
#define FIRD_SPEC_FAMILY 2
#define FIRD_SPEC_HIT_MODE 3
#define FIRD_SPEC_STRICT_POLICY 4
#define FIRD_SPEC_RECORD_WALK 5 // record one ray's RQRM walk (a pipeline of its own)
#define FIRD_SPEC_PROFILE 6     // count walk steps and leaf tests (a pipeline of its own)
#define FIRD_SPEC_DIAGNOSTICS 7 // record hits and count texel hits (a pipeline of its own)
#define FIRD_SPEC_SPREAD 8      // the finish spreads the reflection (a mirror draws nothing)
#define FIRD_SPEC_BOUNCE_KIND 9 // the rays a trace pipeline takes (kBounceEither and so on)
#define FIRD_SPEC_COUNT 10

// Bindings of the fast-path passes.
FIRD_CONSTANT(uint, kBindParams, 0u);
FIRD_CONSTANT(uint, kRaysetBindRays, 1u);
FIRD_CONSTANT(uint, kRaysetBindCounters, 2u);
FIRD_CONSTANT(uint, kRaysetBindBuckets, 3u); // rays per direction bucket (rayset_order.comp)
// R32F view: a photometric emitter's table, or a ray file's rays for the batch
// (kRayFileFloats each)
FIRD_CONSTANT(uint, kRaysetBindEmitterTable, 4u);
FIRD_CONSTANT(uint, kHeightfieldBindHeights, 1u);
FIRD_CONSTANT(uint, kHeightfieldBindGradients, 2u);
FIRD_CONSTANT(uint, kHeightfieldBindControl, 3u); // R32F view: a B-spline's control heights
// The refined surface's heights, at the (W + 1) x (H + 1) texel corners (row-major).
FIRD_CONSTANT(uint, kHeightfieldBindCorners, 4u);
FIRD_CONSTANT(uint, kMaxMipBindPaper, 1u);
FIRD_CONSTANT(uint, kMaxMipBindRefined, 2u);
FIRD_CONSTANT(uint, kMaxMipBindCorners, 3u);
// The levels below, read through R32F image-buffer views of the same buffers (CPU drivers
// gather an image load inline; a storage-buffer load at per-lane indices is a scalar loop
// per lane).
FIRD_CONSTANT(uint, kMaxMipBindPaperIn, 4u);
FIRD_CONSTANT(uint, kMaxMipBindRefinedIn, 5u);
// maxmip.comp's specialization constant: 1 in the pipeline that builds level 0 (the
// refined pyramid's from the corners), 0 in the one for the levels above (one pipeline
// each: CPU drivers would run both bodies for every texel, masked).
// (An id past the scene's constants of common.glsl, which maxmip.comp includes.)
#define FIRD_SPEC_MAXMIP_LEVEL_ZERO FIRD_SPEC_COUNT
// heightfield.comp's and maxmip.comp's: 1 in the pipelines that build only what the refined
// hit mode traces (the corner heights, the refined pyramid), 0 in those that also build the
// paper's (the texel-centre heights and gradients, the paper pyramid), which a refined
// trace of an analytic family never reads: a search's candidates skip them, and the views
// and exports that read them have them built then (FastTracer::read_quadtree).
#define FIRD_SPEC_REFINED_ONLY (FIRD_SPEC_COUNT + 1)
FIRD_CONSTANT(uint, kWalkStartBindPyramid, 1u); // walk_start.comp: the traversal quadtree
FIRD_CONSTANT(uint, kWalkStartBindLevel, 2u);   // uint: the level the source's rays start at
FIRD_CONSTANT(uint, kWalkStartMaxNodes, 4096u); // nodes over the source checked per level
// A ray table holds ray i as RGBA32F texels kRayTexels * i (origin) and the next
// (direction): fastpath/ray_table.hpp, FIRD_LOAD_RAY in common.glsl.
FIRD_CONSTANT(uint, kRayTexels, 2u);
FIRD_CONSTANT(uint, kTraceBindRaysIn, 1u);
FIRD_CONSTANT(uint, kTraceBindRaysOut, 2u);
FIRD_CONSTANT(uint, kTraceBindCounters, 3u);
// Bindings 4-5 are storage texel buffers (R32F), 6 a uniform texel buffer (RG32F); the
// others storage buffers.
FIRD_CONSTANT(uint, kTraceBindPyramid, 4u); // the traversal quadtree of the hit mode
// The hit mode's surface: the paper quadtree (level 0 = texel heights) or the refined
// surface's corner heights.
FIRD_CONSTANT(uint, kTraceBindHeights, 5u);
FIRD_CONSTANT(uint, kTraceBindGradients, 6u);
FIRD_CONSTANT(uint, kTraceBindFarField, 7u);
FIRD_CONSTANT(uint, kTraceBindHits, 8u);
FIRD_CONSTANT(uint, kTraceBindBuckets, 9u);    // rays appended per direction bucket
FIRD_CONSTANT(uint, kTraceBindTexelHits, 10u); // reflections per texel (exports, views)
FIRD_CONSTANT(uint, kTraceBindWalk, 11u);      // the picked ray's walk (FIRD_SPEC_RECORD_WALK)
// Steps a bounce's walk region holds: its [0].x counts them; step k is kWalkStepVec4s vec4s
// from its [1 + 3k]: (level, node x, node y, node max height), (t, t at the node's exit, the
// ray's height at t, its height at the exit), (decision, t it moves to, 0, 0).
FIRD_CONSTANT(uint, kWalkCapacity, 8192u);
FIRD_CONSTANT(uint, kWalkStepVec4s, 3u);
// A step's decision (RQRM, the paper's Algorithms 2-4), as the walk recorded it.
FIRD_CONSTANT(uint, kWalkUndecided, 0u);       // the walk stopped here (its step limit)
FIRD_CONSTANT(uint, kWalkDescend, 1u);         // the ray dips to the node's height inside it: down
FIRD_CONSTANT(uint, kWalkAdvance, 2u);         // above the node: on to the neighbour (a sibling)
FIRD_CONSTANT(uint, kWalkAscend, 3u);          // ... the neighbour lies in a new parent: up a level
FIRD_CONSTANT(uint, kWalkLeave, 4u);           // past the holder or the reflector's top: no hit
FIRD_CONSTANT(uint, kWalkHit, 5u);             // a texel's leaf test found the root
FIRD_CONSTANT(uint, kWalkNoRoot, 6u);          // a texel's leaf test found no root: across it
FIRD_CONSTANT(uint, kWalkOwnTexel, 7u);        // the texel a reflected ray starts from: across it
FIRD_CONSTANT(uint, kTraceBindProfile, 12u);   // the walk's profile (FIRD_SPEC_PROFILE)
FIRD_CONSTANT(uint, kTraceBindWalkStart, 13u); // uint: walk_start.comp's level
// R32F view: a B-spline's control heights (the refined mode reflects about its gradient).
FIRD_CONSTANT(uint, kTraceBindControl, 14u);
// uint[kLoopWords]: the bounce loop's state; the pass traces loop[kLoopActive] rays.
FIRD_CONSTANT(uint, kTraceBindLoop, 15u);
// The profile, per bounce, kProfileFields uints: 64-bit sums as (low, high) pairs of the
// rays traced, their walk steps (quadtree nodes tested), the lane-steps the subgroups
// paid (subgroup size x the steps it ran: a lane waiting for the others pays too), the
// leaf tests (candidate texels tested against the surface) and the lane-leaf-tests paid.
FIRD_CONSTANT(uint, kProfileRays, 0u);
FIRD_CONSTANT(uint, kProfileSteps, 2u);
FIRD_CONSTANT(uint, kProfileLaneSteps, 4u);
FIRD_CONSTANT(uint, kProfileLeafTests, 6u);
FIRD_CONSTANT(uint, kProfileLaneLeafTests, 8u);
FIRD_CONSTANT(uint, kProfileFields, 10u);

// Counter slots (uint) in the counters buffer.
FIRD_CONSTANT(uint, kCounterEffective, 0u); // rays appended by the rayset pass
FIRD_CONSTANT(uint, kCounterDiscarded, 1u);
FIRD_CONSTANT(uint, kCounterBelow, 2u); // born below the surface (a scene error)
FIRD_CONSTANT(uint, kCounterDirect, 3u);
FIRD_CONSTANT(uint, kCounterFarField, 4u);
FIRD_CONSTANT(uint, kCounterLost, 5u);          // strict policy: would hit again
FIRD_CONSTANT(uint, kCounterAborted, 6u);       // traversal bound reached (energy lost)
FIRD_CONSTANT(uint, kCounterActiveOut, 7u);     // rays appended for the next bounce
FIRD_CONSTANT(uint, kCounterByReflections, 8u); // + r: far-field rays with r reflections
// + r: lost rays (below, aborted, blocked, strict) after r reflections, for the flux their
// reflections absorbed before (a material's reflectance below 1).
FIRD_CONSTANT(uint, kCounterLostByReflections, kCounterByReflections + FIRD_MAX_REFLECTIONS + 1u);
FIRD_CONSTANT(uint, kCounterCount, kCounterLostByReflections + FIRD_MAX_REFLECTIONS + 1u);
// The counters buffer holds kTallyCopies copies of the counters: a workgroup adds its
// tallies to copy (workgroup id mod kTallyCopies), so that the threads of a CPU driver do
// not pass one cache line back and forth on every atomic; the host sums the copies. The
// slot allocators (kCounterEffective, kCounterActiveOut) live in copy 0 alone.
FIRD_CONSTANT(uint, kTallyCopies, 64u);

// Everything a pass needs to know about the scene, in one uniform buffer (the scalar
// layout, common.glsl; only 4-byte scalars and arrays of them, so C++ and GLSL agree on
// the layout, as std430's would).
// Positions are relative to the holder box's centre (fastpath/scene_params.hpp).
struct SceneParams {
    float holder_min[4];
    float holder_max[4];
    float source_center[4];
    float source_axis[4];    // the emitter's local +z (emitter.h)
    float source_x_axis[4];  // its local +x (disk, rectangle)
    float source_box_min[4]; // the source's bounding box (walk_start.comp)
    float source_box_max[4];
    float source_length;
    float source_radius;
    float source_width;  // rectangle, along source_x_axis
    float source_height; // rectangle, along source_axis x source_x_axis
    uint source_kind;
    uint source_table_c; // photometric: the emitter table's C and gamma angles (emitter.h)
    uint source_table_g;
    uint sampler_kind; // kSamplerRandom, kSamplerSobol or kSamplerStratified
    uint seed_lo;
    uint seed_hi;
    uint rays_lo; // rays emitted in all (the stratified sampler's strata depend on it)
    uint rays_hi;
    uint family;
    uint bspline_nx;
    uint bspline_ny;
    float params[FIRD_MAX_PARAMS];
    uint hf_w;
    uint hf_h;
    uint levels;
    uint hit_mode;
    uint level_w[FIRD_MAX_LEVELS];
    uint level_h[FIRD_MAX_LEVELS];
    uint level_offset[FIRD_MAX_LEVELS]; // into the quadtree buffer, in floats
    uint ff_w;
    uint ff_h;
    uint max_bounces;
    uint strict_policy;
    uint max_steps;  // traversal bound per ray and bounce
    float offset_mm; // a reflected ray's self-intersection offset (scene_params.cpp)
    // The reflector's finish (material.h): its reflectance (counts_to_lm.comp weighs by
    // it), the lobe's sigma (0: a perfect mirror) and kind.
    float reflectance;
    float spread_rad;
    uint spread_lobe;
    // Far-field counts per reflection order: 1 (every ray weighs the same), or max_bounces
    // + 1 where the reflectance is below 1 (layer k: rays that left after k reflections,
    // weighed R^k by counts_to_lm.comp).
    uint farfield_layers;
    uint bin_direct;        // [trace] direct = "include": rays that leave untouched are binned too
    uint sobol_scramble[5]; // Owen scramble seeds: 4 dimensions, then the index
    uint sobol_directions[4 * 32];
};

struct RaysetPush {
    uint first_lo; // index of the first ray of this batch
    uint first_hi;
    uint count;
    uint keep_all; // measurement only (fird bench --skips): discard no ray before tracing
};

// rayset_order.comp and bucket_scan.comp: the rayset sorted by direction.
#define FIRD_BUCKET_SCAN_WORKGROUP_SIZE 256
FIRD_CONSTANT(uint, kRaysetOrderBits, 8u); // octahedral grid of 2^bits x 2^bits directions
FIRD_CONSTANT(uint, kRaysetOrderBuckets, 1u << (2u * kRaysetOrderBits));
FIRD_CONSTANT(uint, kOrderBindRaysIn, 1u); // (binding 0: the scene parameters)
FIRD_CONSTANT(uint, kOrderBindRaysOut, 2u);
FIRD_CONSTANT(uint, kOrderBindBuckets, 3u); // uint[kRaysetOrderBuckets]: offsets (scanned counts)
FIRD_CONSTANT(uint, kOrderBindLoop, 4u);    // the bounce loop's state (its count and mode)
FIRD_CONSTANT(uint, kScanBindBuckets, 0u);  // bucket_scan.comp's only binding
struct RaysetOrderPush {
    uint reflected; // 1: rays after a bounce (reflected_bucket), 0: the rayset (direction_bucket)
};
// Below this many rays a bounce's output is traced in the order it was appended (the
// ordering would cost more than it saves); rayset_order.comp then copies them as they are.
FIRD_CONSTANT(uint, kOrderMinRays, 1u << 16);

// ---- bounce_args.comp: the bounce loop's counts and dispatch sizes, kept on the device ----
// The trace and the ordering read their ray counts from this uint buffer and are dispatched
// indirectly from it, so the bounces of a batch are recorded together and the host waits
// once (not once per bounce to read the count of rays that reflected).
FIRD_CONSTANT(uint, kLoopTraceArgs, 0u);   // uint[3]: trace.comp's VkDispatchIndirectCommand
FIRD_CONSTANT(uint, kLoopScanArgs, 4u);    // uint[3]: bucket_scan.comp's (1 or 0 groups)
FIRD_CONSTANT(uint, kLoopOrderArgs, 8u);   // uint[3]: rayset_order.comp's
FIRD_CONSTANT(uint, kLoopActive, 12u);     // rays in the input of the bounce traced next
FIRD_CONSTANT(uint, kLoopOrderCount, 13u); // rays rayset_order.comp moves
FIRD_CONSTANT(uint, kLoopSort, 14u);       // 1: it sorts them by direction; 0: it copies them
FIRD_CONSTANT(uint, kLoopBounceRays, 16u); // + b: rays traced in bounce b (read back)
FIRD_CONSTANT(uint, kLoopWords, 16u + FIRD_MAX_REFLECTIONS + 2u);
FIRD_CONSTANT(uint, kBounceArgsBindCounters, 0u);
FIRD_CONSTANT(uint, kBounceArgsBindLoop, 1u);
FIRD_CONSTANT(uint, kArgsOrderRayset, 0u); // the rayset's effective rays, to be sorted
FIRD_CONSTANT(uint, kArgsFirstBounce, 1u); // bounce 0 traces the rayset's effective rays
FIRD_CONSTANT(uint, kArgsNextBounce, 2u);  // bounce `bounce` traces what the one before appended
struct BounceArgsPush {
    uint stage;       // kArgsOrderRayset, kArgsFirstBounce or kArgsNextBounce
    uint bounce;      // the bounce traced next
    uint trace_empty; // measurement only (skip_empty_bounces off): an empty bounce is
                      // still dispatched (one workgroup, whose lanes find no ray)
    uint groups_max;  // maxComputeWorkGroupCount[0]: dispatches are clamped to it (never
                      // reached: a batch holds no more rays than one dispatch covers;
                      // rays left untraced would break the host's energy balance check)
};

// counts_to_lm.comp: the far field's cells, each ray's lumens, and the layers of counts
// per reflection order weighed by the reflectance's powers (SceneParams.farfield_layers).
FIRD_CONSTANT(uint, kToLmBindCounts, 0u); // R32UI view: uint[count * layers]
FIRD_CONSTANT(uint, kToLmBindLumens, 1u); // float[count]
struct ToLmPush {
    uint count;
    float lm_per_ray;
    uint layers;
    float reflectance;
};

struct TracePush {
    uint first_lo;         // the batch's first emission index: a ray's full index from the
    uint first_hi;         // low word it carries in origin.w (a batch holds < 2^32 rays)
    uint bounce;           // reflections so far (0: rays from the source)
    uint final_check;      // strict policy: only test for another hit
    uint record_hits;      // hits[hits_base + i]: input ray i's HitRecord (trace.comp)
    uint hits_base;        // where this bounce's records start (a path's bounces: bounce x rays)
    uint order_output;     // count the appended rays per direction bucket (rayset_order.comp),
                           // where the bounce's input has kOrderMinRays rays or more
    uint count_texel_hits; // texel_hits[t] += reflections at texel t; [W H + t] first ones
    uint walk_ray;         // the emission index (low word) of the ray whose walk is recorded
                           // (FIRD_SPEC_RECORD_WALK), each bounce's at walk[bounce x (1 + 3
                           // kWalkCapacity)]
    uint walk_to_box_top;  // measurement only (fird bench --skips): rising rays are walked
                           // to the holder's top, not to the reflector's highest point
    uint walk_from_root;   // measurement only: the source's rays start at the root, not at
                           // walk_start.comp's level
};

// ---- mesh_raster.comp: a triangle mesh's heights, the paper's z-buffer step (§4.2) ----
#define FIRD_MESH_RASTER_WORKGROUP_SIZE 64
FIRD_CONSTANT(uint, kMeshRasterWorkgroupSize, FIRD_MESH_RASTER_WORKGROUP_SIZE);
// A work item's tile of a triangle's bounding box, texels on a side: a large triangle is
// many items (no invocation loops over more than kMeshRasterTile^2 texels).
FIRD_CONSTANT(uint, kMeshRasterTile, 8u);
FIRD_CONSTANT(uint, kMeshRasterBindTriangles, 0u);  // vec4[3 per triangle]
FIRD_CONSTANT(uint, kMeshRasterBindItems, 1u);      // uvec4 per tile of a triangle
FIRD_CONSTANT(uint, kMeshRasterBindHeightKeys, 2u); // uint per texel: the highest height's key
FIRD_CONSTANT(uint, kMeshRasterBindOwners, 3u);     // uint per texel: 1 + its triangle, or 0
FIRD_CONSTANT(uint, kMeshRasterBindHeights, 4u);    // float per texel (the output)
FIRD_CONSTANT(uint, kMeshRasterBindGradients, 5u);  // vec2 per texel (the output)
// The phases, one dispatch each, in this order.
FIRD_CONSTANT(uint, kMeshRasterHeights, 0u);
FIRD_CONSTANT(uint, kMeshRasterOwners, 1u);
FIRD_CONSTANT(uint, kMeshRasterResolve, 2u); // one invocation per texel
struct MeshRasterPush {
    float raster_min[2]; // the rectangle the width x height texels tile (mm, the fast path's
    float raster_max[2]; // frame: scene_params.hpp)
    float floor_mm;      // the holder's z range, which heights are clamped to
    float ceiling_mm;
    uint width;
    uint height;
    uint item_count; // work items (phases 0 and 1)
    uint phase;
    uint row_stride; // invocations per row of the dispatch's grid (x groups * workgroup size)
    // The first and last texel centres, computed on the host in double: the shader's float
    // centres are clamped to them, so that the corners' raster (a grid half a texel wider
    // than the holder) puts its outermost centres exactly on the rim of a mesh flush with
    // the holder, where a float sum could land an ulp outside and read the floor.
    float centre_min[2];
    float centre_max[2];
    uint pad0;
};

struct MaxMipPush {
    uint level; // building this level from level - 1 (0: from the height texture)
    uint pad0;
    uint pad1;
    uint pad2;
};

#ifdef __cplusplus
} // namespace fird::gpu
#endif
#endif
