#version 450
// Two lights and a rim so the shape reads; optionally coloured by height or by slope (the
// vertex shader puts either in height01), or by curvature (worked out here).
layout(location = 0) in vec3 normal;
layout(location = 1) in float height01;
layout(location = 2) in vec2 slope_gradient;
layout(location = 3) in vec2 plane_mm;
layout(location = 0) out vec4 colour;
layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 grid;
    vec4 shade;
    uvec4 size;
} pc;

vec3 height_colour(float t) { // dark blue - teal - yellow
    return mix(mix(vec3(0.16, 0.20, 0.45), vec3(0.10, 0.62, 0.60), clamp(2.0 * t, 0.0, 1.0)),
               vec3(0.98, 0.86, 0.30), clamp(2.0 * t - 1.0, 0.0, 1.0));
}

// The larger principal curvature (1/mm) of z = f(x, y) where the gradient is interpolated
// across the triangle: its Hessian [[r, s], [s, t]] is the gradient's derivative along the
// press plane, d(gradient)/d(screen) times the inverse of d(plane)/d(screen) (constant
// over a triangle, so the screen drops out: the curvature of the mesh's finite
// differences, whatever the view). Mean and Gaussian curvatures as press_measures.cpp
// takes them; 0 where the triangle is seen edge-on (no plane derivative to invert).
float largest_curvature() {
    const mat2 dg = mat2(dFdx(slope_gradient), dFdy(slope_gradient));
    const mat2 dp = mat2(dFdx(plane_mm), dFdy(plane_mm));
    const float det = determinant(dp);
    const float scale = dot(dp[0], dp[0]) + dot(dp[1], dp[1]);
    if (abs(det) <= 1e-6 * scale) return 0.0;
    const mat2 h = dg * inverse(dp); // h[c][r]: column c, row r
    const float r = h[0][0], t = h[1][1], s = 0.5 * (h[1][0] + h[0][1]);
    const float p = slope_gradient.x, q = slope_gradient.y;
    const float w = 1.0 + p * p + q * q;
    const float mean = ((1.0 + q * q) * r - 2.0 * p * q * s + (1.0 + p * p) * t) /
                       (2.0 * pow(w, 1.5));
    const float gauss = (r * t - s * s) / (w * w);
    return abs(mean) + sqrt(max(mean * mean - gauss, 0.0));
}

void main() {
    const vec3 n = normalize(normal);
    const vec3 key = normalize(vec3(-0.45, -0.55, 0.70));
    const vec3 fill = normalize(vec3(0.6, 0.3, 0.4));
    // Lit from both sides: the reflector is seen from above and, through the holder, below.
    const float light = 0.25 + 0.6 * abs(dot(n, key)) + 0.2 * abs(dot(n, fill));
    float t = height01;
    if (pc.shade.z > 2.5) // log10 of the curvature between the scale's ends
        t = clamp((log(max(largest_curvature(), 1e-30)) / log(10.0) - pc.shade.x) /
                      (pc.shade.y - pc.shade.x),
                  0.0, 1.0);
    const vec3 base = pc.shade.z > 0.5 ? height_colour(t) : vec3(0.72, 0.75, 0.80);
    colour = vec4(base * light, 1.0);
}
