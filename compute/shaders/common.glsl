// Shared GLSL for the fast path: the scene parameters, Philox and Sobol, the light
// reflector families (the GLSL twins of compute/sampling and model/; the sources are
// source.glsl's).
#ifndef FIRD_COMMON_GLSL
#define FIRD_COMMON_GLSL

#extension GL_GOOGLE_include_directive : require
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#extension GL_EXT_scalar_block_layout : require
#include "fird_shared.h"

// A uniform buffer, not a storage buffer: every invocation reads it at the same address,
// and CPU drivers (llvmpipe) load a storage buffer inside divergent control flow (after
// any early return) in a loop over the lanes, each with a bounds check, even at a uniform
// address, where a uniform buffer's load is one scalar load. The scalar layout is the C
// struct's (SceneParams holds 4-byte scalars and arrays of them: std430's offsets).
layout(scalar, binding = kBindParams) uniform Params { SceneParams P; };

// The scene's fixed choices (SceneParams holds the same values for the host).
layout(constant_id = FIRD_SPEC_SOURCE_KIND) const uint kSourceKind = 0u;
layout(constant_id = FIRD_SPEC_SAMPLER_KIND) const uint kSamplerKind = 0u;
layout(constant_id = FIRD_SPEC_FAMILY) const uint kFamily = 0u;
layout(constant_id = FIRD_SPEC_HIT_MODE) const uint kHitMode = 0u;
layout(constant_id = FIRD_SPEC_RECORD_WALK) const uint kRecordWalk = 0u;
layout(constant_id = FIRD_SPEC_STRICT_POLICY) const uint kStrictPolicy = 0u;
layout(constant_id = FIRD_SPEC_PROFILE) const uint kProfile = 0u;
layout(constant_id = FIRD_SPEC_DIAGNOSTICS) const uint kDiagnostics = 0u;
layout(constant_id = FIRD_SPEC_SPREAD) const uint kSpread = 0u;
layout(constant_id = FIRD_SPEC_BOUNCE_KIND) const uint kBounceKind = kBounceEither;

const float kPi = 3.14159265358979;

struct Ray {
    vec4 origin;
    vec4 direction;
};

// Philox4x32-10, as sampling/philox.hpp.
uvec4 philox(uvec4 c, uvec2 k) {
    for (int r = 0; r < 10; ++r) {
        uint hi0, lo0, hi1, lo1;
        umulExtended(0xD2511F53u, c.x, hi0, lo0);
        umulExtended(0xCD9E8D57u, c.z, hi1, lo1);
        c = uvec4(hi1 ^ c.y ^ k.x, lo1, hi0 ^ c.w ^ k.y, lo0);
        k += uvec2(0x9E3779B9u, 0xBB67AE85u);
    }
    return c;
}

// Uniforms in (0, 1): the top 24 bits, at cell midpoints (exact in float).
vec4 to_unit(uvec4 bits) { return (vec4(bits >> 8u) + 0.5) * (1.0 / 16777216.0); }
vec2 to_unit(uvec2 bits) { return (vec2(bits >> 8u) + 0.5) * (1.0 / 16777216.0); }

uint lk_permute(uint x, uint seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}
uint owen_scramble(uint x, uint seed) { return bitfieldReverse(lk_permute(bitfieldReverse(x), seed)); }

// Gathers the even bits of x into its low 16 bits (inverse of a Morton spread).
uint compact_bits(uint x) {
    x &= 0x55555555u;
    x = (x | (x >> 1u)) & 0x33333333u;
    x = (x | (x >> 2u)) & 0x0f0f0f0fu;
    x = (x | (x >> 4u)) & 0x00ff00ffu;
    x = (x | (x >> 8u)) & 0x0000ffffu;
    return x;
}

// a > b for 64-bit (high, low) pairs.
bool greater_u64(uvec2 a, uvec2 b) { return a.x > b.x || (a.x == b.x && a.y > b.y); }

// q * N as a 64-bit (high, low) pair (q < 2^17, N = rays emitted).
uvec2 times_rays(uint q) {
    uint hi, lo;
    umulExtended(q, P.rays_lo, hi, lo);
    return uvec2(hi + q * P.rays_hi, lo);
}


// As sampling/strata.hpp: the stratum of ray `index` is floor((index * kStrata + s) / rays)
// for kStrataBits random bits s, in exact integer arithmetic (a float quotient, then
// corrected: it is off by at most one).
uint stratum(uint index_lo, uint index_hi, uint s) {
    const uvec2 num = uvec2((index_hi << kStrataBits) | (index_lo >> (32u - kStrataBits)),
                            (index_lo << kStrataBits) | s);
    const float rays = float(P.rays_hi) * 4294967296.0 + float(P.rays_lo);
    uint q = uint(min((float(num.x) * 4294967296.0 + float(num.y)) / rays, float(kStrata - 1u)));
    for (int k = 0; k < 2; ++k)
        if (q > 0u && greater_u64(times_rays(q), num)) --q;
    for (int k = 0; k < 2; ++k)
        if (q + 1u < kStrata && !greater_u64(times_rays(q + 1u), num)) ++q;
    return q;
}

vec4 ray_uniforms(uint index_lo, uint index_hi) {
    if (kSamplerKind == kSamplerStratified) {
        const uvec4 w = philox(uvec4(index_lo, index_hi, 0u, 0u), uvec2(P.seed_lo, P.seed_hi));
        const uint c = stratum(index_lo, index_hi, w.x >> (32u - kStrataBits));
        // The cell's corner plus a uniform offset inside it: 23 bits and a half, exact in float.
        const uvec2 cell = uvec2(compact_bits(c), compact_bits(c >> 1u));
        const uint bits = kStratumOffsetBits;
        const uvec2 offset = uvec2(w.y >> (32u - bits), (w.y >> (32u - 2u * bits)) & ((1u << bits) - 1u));
        const vec2 u01 = (vec2((cell << bits) | offset) + 0.5) * (1.0 / 8388608.0);
        return vec4(u01, to_unit(w.zw));
    }
    if (kSamplerKind == kSamplerRandom)
        return to_unit(philox(uvec4(index_lo, index_hi, 0u, 0u), uvec2(P.seed_lo, P.seed_hi)));
    const uint i = owen_scramble(index_lo, P.sobol_scramble[4]);
    uvec4 x = uvec4(0u);
    for (uint b = 0u; b < 32u; ++b) {
        if (((i >> b) & 1u) == 0u) continue;
        x ^= uvec4(P.sobol_directions[b], P.sobol_directions[32u + b], P.sobol_directions[64u + b],
                   P.sobol_directions[96u + b]);
    }
    x = uvec4(owen_scramble(x.x, P.sobol_scramble[0]), owen_scramble(x.y, P.sobol_scramble[1]),
              owen_scramble(x.z, P.sobol_scramble[2]), owen_scramble(x.w, P.sobol_scramble[3]));
    return to_unit(x);
}

vec3 holder_min() { return vec3(P.holder_min[0], P.holder_min[1], P.holder_min[2]); }
vec3 holder_max() { return vec3(P.holder_max[0], P.holder_max[1], P.holder_max[2]); }

// Slab test of the forward half-line against the box lo..hi; t range in t01.
bool clip_to_box(vec3 o, vec3 d, vec3 lo, vec3 hi, out vec2 t01) {
    float t0 = 0.0;
    float t1 = 3.0e38;
    for (int k = 0; k < 3; ++k) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return false;
            continue;
        }
        float ta = (lo[k] - o[k]) / d[k];
        float tb = (hi[k] - o[k]) / d[k];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    t01 = vec2(t0, t1);
    return t0 <= t1;
}

// Per-subgroup aggregation: one atomic per subgroup instead of one per ray on the same
// counter (every ray touches the same few counters; serialized atomics dominated), into
// this workgroup's copy of the counters (kTallyCopies).
#define FIRD_COUNT(counter_array, slot, condition)                                          \
    {                                                                                      \
        const uint fird_n_ = subgroupBallotBitCount(subgroupBallot(condition));            \
        const uint fird_copy_ = (gl_WorkGroupID.x % kTallyCopies) * kCounterCount;          \
        if (fird_n_ > 0u && subgroupElect()) atomicAdd(counter_array[fird_copy_ + (slot)], fird_n_); \
    }

// Ray i of a ray table (an rgba32ui uimageBuffer: fastpath/ray_table.hpp), read and
// written as two texels. (A storage buffer's Ray at a per-lane index is, on CPU drivers, a
// loop over the lanes with every component bounds-checked apart.) The texels are integers
// so that the bits go through as they are: origin.w and direction.w carry integers (the
// emission index, the texel), which as floats are denormals or NaN payloads that a float
// format's load or store would be free to flush.
#define FIRD_LOAD_RAY(table, i)                                     \
    Ray(uintBitsToFloat(imageLoad(table, int(kRayTexels * (i)))), \
        uintBitsToFloat(imageLoad(table, int(kRayTexels * (i) + 1u))))
#define FIRD_STORE_RAY(table, i, ray)                                                 \
    {                                                                                 \
        imageStore(table, int(kRayTexels * (i)), floatBitsToUint((ray).origin));        \
        imageStore(table, int(kRayTexels * (i) + 1u), floatBitsToUint((ray).direction)); \
    }

// Appends where `condition` holds: returns each such lane's slot in the output array.
#define FIRD_APPEND_INDEX(counter_array, slot, condition, out_index)                        \
    {                                                                                      \
        const uvec4 fird_b_ = subgroupBallot(condition);                                   \
        const uint fird_n_ = subgroupBallotBitCount(fird_b_);                              \
        uint fird_base_ = 0u;                                                              \
        if (subgroupElect() && fird_n_ > 0u) fird_base_ = atomicAdd(counter_array[slot], fird_n_); \
        out_index = subgroupBroadcastFirst(fird_base_) + subgroupBallotExclusiveBitCount(fird_b_); \
    }

#endif
