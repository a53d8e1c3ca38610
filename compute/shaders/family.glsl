// The reflector families in GLSL (float), as model/surface.cpp: raw height and gradient.
// heightfield.comp evaluates them at texel centres and corners; trace.comp at a hit point
// (the refined mode reflects about the family's own gradient there).
#ifndef FIRD_FAMILY_GLSL
#define FIRD_FAMILY_GLSL
#include "common.glsl"

float spow(float x, float p) { return x <= 0.0 ? 0.0 : pow(x, p); }

// params: plane (z0, sx, sy, cx, cy); paraboloid (fx, fy, z0, cx, cy);
// cup (a, b, p, h, z0, cx, cy); fluted cup (a, p, h, w, z0, cx, cy).
vec3 family_height_gradient(float x, float y) {
    const uint f = kFamily;
    if (f == kFamilyPlane) {
        return vec3(P.params[0] + P.params[1] * (x - P.params[3]) + P.params[2] * (y - P.params[4]),
                    P.params[1], P.params[2]);
    }
    if (f == kFamilyParaboloid) {
        const float u = x - P.params[3];
        const float v = y - P.params[4];
        return vec3(P.params[2] + u * u / (4.0 * P.params[0]) + v * v / (4.0 * P.params[1]),
                    u / (2.0 * P.params[0]), v / (2.0 * P.params[1]));
    }
    if (f == kFamilyCup) {
        const float a = P.params[0], b = P.params[1], p = P.params[2], h = P.params[3];
        const float u = x - P.params[5];
        const float v = y - P.params[6];
        const float z = P.params[4] + h * spow(abs(u) / a, p) + h * spow(abs(v) / b, p);
        const float gx = h * p * spow(abs(u) / a, p - 1.0) / a * sign(u);
        const float gy = h * p * spow(abs(v) / b, p - 1.0) / b * sign(v);
        return vec3(z, gx, gy);
    }
    // Fluted cup.
    const float a = P.params[0], p = P.params[1], h = P.params[2], w = P.params[3];
    const float u = x - P.params[5];
    const float v = y - P.params[6];
    const float r = length(vec2(u, v));
    const float rho = r / a;
    const float psi = r > 0.0 ? atan(v, u) : 0.0; // atan(0, 0) may be NaN on some drivers
    const float z = P.params[4] + h * spow(rho, p) + w * rho * cos(8.0 * psi);
    if (r == 0.0) return vec3(z, 0.0, 0.0);
    const float dz_drho = h * p * spow(rho, p - 1.0) + w * cos(8.0 * psi);
    const float dz_dpsi = -8.0 * w * rho * sin(8.0 * psi);
    return vec3(z, dz_drho * u / (r * a) - dz_dpsi * v / (r * r), dz_drho * v / (r * a) + dz_dpsi * u / (r * r));
}

// A B-spline's control height k (row-major, nx per row): each includer binds the buffer.
float control_height(int k);

// Uniform cubic B-spline basis at t in [0, 1] and its derivative.
void bspline_basis(float t, out vec4 b, out vec4 db) {
    const float s = 1.0 - t;
    b = vec4(s * s * s, 3.0 * t * t * t - 6.0 * t * t + 4.0, -3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0, t * t * t) / 6.0;
    db = vec4(-s * s / 2.0, (9.0 * t * t - 12.0 * t) / 6.0, (-9.0 * t * t + 6.0 * t + 3.0) / 6.0, t * t / 2.0);
}

// The B-spline over the holder rectangle, its control grid spanning it (clamped ends).
vec3 bspline_height_gradient(float x, float y) {
    const int nx = int(P.bspline_nx), ny = int(P.bspline_ny);
    const vec3 lo = holder_min(), hi = holder_max();
    const float dx = (hi.x - lo.x) / float(nx - 1), dy = (hi.y - lo.y) / float(ny - 1);
    const float sx = clamp((x - lo.x) / dx, 0.0, float(nx - 1));
    const float sy = clamp((y - lo.y) / dy, 0.0, float(ny - 1));
    const int i = min(int(sx), nx - 2), j = min(int(sy), ny - 2);
    vec4 bx, dbx, by, dby;
    bspline_basis(sx - float(i), bx, dbx);
    bspline_basis(sy - float(j), by, dby);
    vec3 r = vec3(0.0);
    for (int m = 0; m < 4; ++m)
        for (int k = 0; k < 4; ++k) {
            const float h = control_height(clamp(j - 1 + m, 0, ny - 1) * nx + clamp(i - 1 + k, 0, nx - 1));
            r += h * vec3(by[m] * bx[k], by[m] * dbx[k] / dx, dby[m] * bx[k] / dy);
        }
    return r;
}

// The profile (model/surface.hpp ProfileFn): z0 + f(r) about (cx, cy), f the uniform cubic
// B-spline with knots every `spacing` mm; control_height(k) is its control point c_(k-1),
// k = 0 .. spans + 2 (the host solves them from the heights). Constant past the last knot.
vec3 profile_height_gradient(float x, float y) {
    const float u = x - P.params[1], v = y - P.params[2];
    const float r = length(vec2(u, v));
    const int spans = int(P.bspline_nx) - 1;
    const float s = r / P.params[3];
    if (s >= float(spans))
        return vec3(P.params[0] + (control_height(spans) + 4.0 * control_height(spans + 1) + control_height(spans + 2)) / 6.0, 0.0, 0.0);
    const int i = min(int(s), spans - 1);
    vec4 b, db;
    bspline_basis(s - float(i), b, db);
    const vec4 c = vec4(control_height(i), control_height(i + 1), control_height(i + 2), control_height(i + 3));
    const float slope = dot(db, c) / P.params[3];
    // f'(0) = 0 by construction: the axis itself has no direction to slope along.
    const vec2 g = r > 0.0 ? slope * vec2(u, v) / r : vec2(0.0);
    return vec3(P.params[0] + dot(b, c), g);
}

// The reflector's raw (unclamped) height and gradient at (x, y), any analytic family.
vec3 reflector_height_gradient(vec2 xy) {
    if (kFamily == kFamilyBSpline) return bspline_height_gradient(xy.x, xy.y);
    if (kFamily == kFamilyProfile) return profile_height_gradient(xy.x, xy.y);
    return family_height_gradient(xy.x, xy.y);
}

#endif
