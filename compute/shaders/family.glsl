// The reflector families in GLSL (float), as model/surface.cpp: raw height and gradient.
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

#endif
