// One definition of a reflection (DESIGN.md §2, [reflector.material]): the mirror law and
// the finish's spread about it, as a function of the incoming direction, the surface
// normal and two uniforms in (0, 1). GLSL compiles it in float (trace.comp), C++ in double
// (the CPU reference), so both tracers reflect by this one text; the uniforms come from
// the counter-based stream (seed, ray index, kMaterialStream + bounce) on both.
//
// The reflectance is not sampled: a ray keeps its whole count, and the far field weighs
// the rays that left after k reflections by R^k (counts_to_lm.comp), so the absorbed flux
// is exact, not a Monte Carlo estimate.
#ifndef FIRD_MATERIAL_H
#define FIRD_MATERIAL_H

#include "frame.h"

#ifdef __cplusplus
namespace fird::gpu::emission {
using std::asin;
using std::exp;
#endif

// The mirror direction of unit d about unit normal n (d . n < 0: the side n points to).
FIRD_SHARED_INLINE vec3 mirror_direction(vec3 d, vec3 n) {
    return normalize(d - 2.0 * dot(d, n) * n);
}

// 1 - e^x for x <= 0, without the cancellation of 1 - (a float near 1): its series where
// |x| < 1e-2 (truncated after x^4: 1e-10 relative).
FIRD_SHARED_INLINE real_t one_minus_exp(real_t x) {
    if (x > -0.01) return -x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x / 24.0)));
    return 1.0 - exp(x);
}

// The polar angle of the spread lobe about the mirror direction for a uniform u in (0, 1).
// Gaussian: theta = sigma sqrt(-2 ln u) (a Rayleigh angle), so that the deviation's two
// components in the tangent plane about the mirror direction (theta cos phi, theta sin
// phi: its exponential map) are independent normals of standard deviation sigma, which is
// what spread_deg states and the tests measure. Phong: the cos^n lobe (pdf per solid
// angle), n = 1 / sigma^2, whose small-angle form is that same Gaussian: its sigma per
// axis is spread_deg within 1 % up to 5 degrees, 2.4 % low at 10, 17 % low at 30.
FIRD_SHARED_INLINE real_t spread_angle(real_t u, real_t sigma_rad, uint lobe) {
    if (lobe == kLobePhong) {
        // cos theta = u^(1 / (n + 1)); theta from 1 - cos theta = 2 sin^2(theta / 2), which
        // keeps its precision at the small angles of a tight lobe (acos near 1 would not).
        const real_t n = 1.0 / (sigma_rad * sigma_rad);
        const real_t one_minus_cos = one_minus_exp(log(u) / (n + 1.0));
        return 2.0 * asin(sqrt(min(real_t(1.0), 0.5 * one_minus_cos)));
    }
    return min(real_t(kSharedPi), sigma_rad * sqrt(-2.0 * log(u)));
}

// The reflected direction: the mirror direction of d about n, turned by the finish's lobe.
// A lobe direction below the surface (d' . n <= 0, near grazing) is folded back across the
// tangent plane, so that a reflected ray never points into the surface and no ray is lost
// to the finish: the flux stays exactly accounted for.
FIRD_SHARED_INLINE vec3 reflected_direction(vec3 d, vec3 n, real_t sigma_rad, uint lobe, real_t u1,
                                            real_t u2) {
    const vec3 m = mirror_direction(d, n);
    if (sigma_rad <= 0.0) return m;
    const real_t theta = spread_angle(u1, sigma_rad, lobe);
    const real_t phi = 2.0 * kSharedPi * u2;
    const Basis f = basis_about(m);
    vec3 r = cos(theta) * m + sin(theta) * (cos(phi) * f.t + sin(phi) * f.b);
    const real_t below = dot(r, n);
    if (below <= 0.0) r = r - 2.0 * below * n;
    return dot(r, n) > 0.0 ? normalize(r) : m;
}

#ifdef __cplusplus
} // namespace fird::gpu::emission
#endif
#endif
