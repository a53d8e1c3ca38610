// One definition of the light sources' emission (DESIGN.md §2): where an emitter's ray
// starts and where it leaves, as a function of four uniforms in (0, 1). GLSL compiles it
// in float (common.glsl, for rayset.comp); C++ in double (model/source.cpp, for the CPU
// reference), so both tracers sample their rays from this one text. A new emitter is a
// kind in fird_shared.h, a branch in sample_emitter and its keys in the scene file.
//
// The text is the common subset of GLSL and C++ with glm that frame.h sets up.
#ifndef FIRD_EMITTER_H
#define FIRD_EMITTER_H

#include "frame.h"

#ifdef __cplusplus
namespace fird::gpu::emission {
// A photometric emitter's table (emission_table.hpp lays it out): a pointer in C++, the
// rayset pass's texel view `emitter_table` in GLSL (source.glsl binds it and defines
// FIRD_TABLE_AT, float k of the table, as its load).
#define FIRD_TABLE_ARG , const float* emitter_table
#define FIRD_TABLE_PASS , emitter_table
#define FIRD_TABLE_AT(k) emitter_table[k]
#else
#define FIRD_TABLE_ARG
#define FIRD_TABLE_PASS
#endif

// An emitter in the frame its tracer works in. `axis` is the emitter's local +z (unit): a
// cylinder's axis, a cosine point's axis, a disk's or rectangle's normal (the emitting
// side). `x_axis` is its local +x (unit, perpendicular to axis; disk and rectangle), and
// its local +y is axis x x_axis, so that (x, y, z) is right-handed.
struct Emitter {
    uint kind; // kSourceCylinder, ... (fird_shared.h)
    vec3 center;
    vec3 axis;
    vec3 x_axis;
    real_t length_mm; // cylinder, along its axis
    real_t radius_mm; // cylinder, sphere, disk
    real_t width_mm;  // rectangle, along x_axis
    real_t height_mm; // rectangle, along axis x x_axis
    // photometric: the table's C angles (the first repeated at 360 degrees) and gamma
    // angles; a radius_mm above 0 emits from a disk across the axis, else from the centre.
    uint table_c;
    uint table_g;
};

struct Emission {
    vec3 origin;
    vec3 direction; // unit length
};

// A Lambertian (cosine-weighted) direction about unit n, in the frame (t, b, n).
FIRD_SHARED_INLINE vec3 cosine_direction_in(vec3 n, vec3 t, vec3 b, real_t u1, real_t u2) {
    const real_t r = sqrt(u1);
    const real_t phi = 2.0 * kSharedPi * u2;
    const real_t cos_theta = sqrt(max(real_t(0.0), real_t(1.0) - u1));
    return normalize(r * cos(phi) * t + r * sin(phi) * b + cos_theta * n);
}

FIRD_SHARED_INLINE vec3 cosine_direction(vec3 n, real_t u1, real_t u2) {
    const Basis f = basis_about(n);
    return cosine_direction_in(n, f.t, f.b, u1, u2);
}

FIRD_SHARED_INLINE vec3 uniform_sphere(real_t u1, real_t u2) {
    const real_t z = 1.0 - 2.0 * u1;
    const real_t r = sqrt(max(real_t(0.0), real_t(1.0) - z * z));
    const real_t phi = 2.0 * kSharedPi * u2;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// A point uniform on the unit disk from two uniforms (Shirley and Chiu's concentric map):
// continuous and area-preserving, and a stratum's image is compact wherever it lies (the
// polar map's strata near the centre are thin wedges).
FIRD_SHARED_INLINE vec2 concentric_disk(real_t u1, real_t u2) {
    const real_t a = 2.0 * u1 - 1.0;
    const real_t b = 2.0 * u2 - 1.0;
    if (a == 0.0 && b == 0.0) return vec2(0.0, 0.0);
    const real_t quarter_pi = 0.25 * kSharedPi;
    const bool wide = abs(a) > abs(b);
    const real_t r = wide ? a : b;
    const real_t angle = wide ? quarter_pi * (b / a) : 2.0 * quarter_pi - quarter_pi * (a / b);
    return vec2(r * cos(angle), r * sin(angle));
}

// t in [0, 1) under the density proportional to a (1 - t) + b t, for the uniform u:
// the root of (a t + (b - a) t^2 / 2) / ((a + b) / 2) = u, in the form without
// cancellation (and t = u where a = b).
FIRD_SHARED_INLINE real_t linear_density_inverse(real_t a, real_t b, real_t u) {
    const real_t root = sqrt(max(real_t(0.0), a * a + (b * b - a * a) * u));
    const real_t denominator = a + root;
    return denominator > 0.0 ? min(u * (a + b) / denominator, real_t(1.0)) : u;
}

// A photometric emitter's direction in its local frame (C = 0 along +x, C = 90 along +y,
// gamma = 0 the nadir, local -z: d = (sin g cos C, sin g sin C, -cos g)), exactly under the
// table's interpolation (photometry/candela_table.hpp: linear in C and in cos gamma, so
// bilinear in (C, cos gamma), where the solid angle is dC dcos(gamma)). The table holds C
// (radians, table_c), cos gamma (table_g), the intensity at each (C, gamma) and the
// cumulative flux of each cell (C_j..C_j+1, gamma_i..gamma_i+1), cell j (table_g - 1) + i,
// normalised to end at 1. u.x picks the cell (its remainder, the cos gamma inside it), u.y
// the C inside it.
FIRD_SHARED_INLINE vec3 photometric_direction(uint nc, uint ng, real_t ux,
                                              real_t uy FIRD_TABLE_ARG) {
    const uint cells = (nc - 1u) * (ng - 1u);
    const uint cdf_at = nc + ng + nc * ng;
    // The first cell whose cumulative flux exceeds ux (binary search, at most 32 steps).
    uint lo = 0u;
    uint hi = cells - 1u;
    for (int step = 0; step < 32 && lo < hi; ++step) {
        const uint mid = (lo + hi) / 2u;
        if (real_t(FIRD_TABLE_AT(cdf_at + mid)) > ux)
            hi = mid;
        else
            lo = mid + 1u;
    }
    const uint j = lo / (ng - 1u);
    const uint i = lo - j * (ng - 1u);
    const real_t before = lo > 0u ? real_t(FIRD_TABLE_AT(cdf_at + lo - 1u)) : real_t(0.0);
    const real_t share = real_t(FIRD_TABLE_AT(cdf_at + lo)) - before;
    const real_t v =
        share > 0.0 ? min(max((ux - before) / share, real_t(0.0)), real_t(1.0)) : real_t(0.5);
    const uint cd_at = nc + ng;
    const real_t i00 = real_t(FIRD_TABLE_AT(cd_at + j * ng + i));
    const real_t i01 = real_t(FIRD_TABLE_AT(cd_at + j * ng + i + 1u));
    const real_t i10 = real_t(FIRD_TABLE_AT(cd_at + (j + 1u) * ng + i));
    const real_t i11 = real_t(FIRD_TABLE_AT(cd_at + (j + 1u) * ng + i + 1u));
    // cos gamma first (its marginal is linear), then C at that cos gamma (linear too).
    const real_t tg = linear_density_inverse(i00 + i10, i01 + i11, v);
    const real_t tc = linear_density_inverse(i00 + (i01 - i00) * tg, i10 + (i11 - i10) * tg, uy);
    const real_t mu0 = real_t(FIRD_TABLE_AT(nc + i));
    const real_t mu1 = real_t(FIRD_TABLE_AT(nc + i + 1u));
    const real_t c0 = real_t(FIRD_TABLE_AT(j));
    const real_t c1 = real_t(FIRD_TABLE_AT(j + 1u));
    const real_t mu = mu0 + (mu1 - mu0) * tg;
    const real_t c = c0 + (c1 - c0) * tc;
    const real_t sin_g = sqrt(max(real_t(0.0), real_t(1.0) - mu * mu));
    return vec3(sin_g * cos(c), sin_g * sin(c), -mu);
}

// cylinder: uniform on the lateral surface (the caps dark), Lambertian about the outward
// normal, the direction sampled first: a point's normal n = (cos phi, sin phi) across the
// axis (phi uniform) and a direction d at cosine c to the axis and azimuth psi have the joint
// density max(0, n.d) ~ max(0, sqrt(1 - c^2) cos(phi - psi)), so d has the density
// sqrt(1 - c^2) / pi^2 per steradian (uniform in psi, a cylinder's projected area), and
// given d the normal is at phi - psi = asin(w) for w uniform in [-1, 1]. A point uniform
// on the unit disk has x under that semicircle law and y uniform in [-sqrt(1 - x^2),
// sqrt(1 - x^2)] given x: the disk from the first two uniforms (concentric_disk) gives c
// and psi, so a stratified rayset comes ordered by direction. sphere: uniform on the surface,
// Lambertian about the outward normal, the direction sampled first: the joint density of the normal
// n (uniform) and the direction d (Lambertian about n) is max(0, n.d) / (4 pi^2), symmetric in n
// and d, so d uniform and n Lambertian about d is the same distribution, and the direction comes
// from the stratified first two uniforms. point: isotropic, or Lambertian about `axis`. disk and
// rectangle: one-sided Lambertian about `axis`, uniform over the area; the direction from
// the first two uniforms for the same reason (a stratified rayset then comes ordered by
// direction, fird_shared.h's rayset_ordered_at_birth).
// photometric: the direction from the table (photometric_direction) turned into the scene
// by (x_axis, axis x x_axis, axis), the point the centre or uniform over a disk across the
// axis.
FIRD_SHARED_INLINE Emission sample_emitter(Emitter e, vec4 u FIRD_TABLE_ARG) {
    Emission r;
    if (e.kind == kSourceCylinder) {
        const Basis f = basis_about(e.axis);
        const vec2 p = concentric_disk(u.x, u.y);
        const real_t c = p.x;
        const real_t s = sqrt(max(real_t(0.0), real_t(1.0) - c * c));
        const real_t v = s > 0.0 ? min(max(p.y / s, real_t(-1.0)), real_t(1.0)) : real_t(0.0);
        // psi = pi v, in [-pi, pi] (where Vulkan bounds sin's and cos's error): v = -1 and
        // v = 1 are the same azimuth, so the map from the square to the directions is
        // continuous (neighbouring strata, nearby directions).
        const real_t psi = kSharedPi * v;
        const vec3 across = cos(psi) * f.t + sin(psi) * f.b; // d's heading across the axis
        const vec3 beside = cross(e.axis, across);
        r.direction = c * e.axis + s * across;
        // The normal at phi = psi + asin(w): cos and sin of asin(w) without the inverse.
        const real_t w = 2.0 * u.z - 1.0;
        const vec3 n = sqrt(max(real_t(0.0), real_t(1.0) - w * w)) * across + w * beside;
        r.origin = e.center + (u.w - 0.5) * e.length_mm * e.axis + e.radius_mm * n;
    } else if (e.kind == kSourceSphere) {
        r.direction = uniform_sphere(u.x, u.y);
        r.origin = e.center + e.radius_mm * cosine_direction(r.direction, u.z, u.w);
    } else if (e.kind == kSourcePointCosine) {
        r.origin = e.center;
        r.direction = cosine_direction(e.axis, u.x, u.y);
    } else if (e.kind == kSourcePhotometric) {
        const vec3 y_axis = cross(e.axis, e.x_axis);
        const vec3 d = photometric_direction(e.table_c, e.table_g, u.x, u.y FIRD_TABLE_PASS);
        r.direction = normalize(d.x * e.x_axis + d.y * y_axis + d.z * e.axis);
        const real_t rho = e.radius_mm * sqrt(u.z);
        const real_t phi = 2.0 * kSharedPi * u.w;
        r.origin = e.center + rho * cos(phi) * e.x_axis + rho * sin(phi) * y_axis;
    } else if (e.kind == kSourceDisk || e.kind == kSourceRectangle) {
        const vec3 y_axis = cross(e.axis, e.x_axis);
        r.direction = cosine_direction_in(e.axis, e.x_axis, y_axis, u.x, u.y);
        if (e.kind == kSourceDisk) {
            // Uniform over the area: radius sqrt(u) R.
            const real_t rho = e.radius_mm * sqrt(u.z);
            const real_t phi = 2.0 * kSharedPi * u.w;
            r.origin = e.center + rho * cos(phi) * e.x_axis + rho * sin(phi) * y_axis;
        } else {
            r.origin =
                e.center + (u.z - 0.5) * e.width_mm * e.x_axis + (u.w - 0.5) * e.height_mm * y_axis;
        }
    } else {
        r.origin = e.center;
        r.direction = uniform_sphere(u.x, u.y);
    }
    return r;
}

#undef FIRD_TABLE_ARG
#undef FIRD_TABLE_PASS
#ifdef __cplusplus
#undef FIRD_TABLE_AT
} // namespace fird::gpu::emission
#endif
#endif
