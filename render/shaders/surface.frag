#version 450
// Two lights and a rim so the shape reads; optionally coloured by height or by slope (the
// vertex shader puts either in height01).
layout(location = 0) in vec3 normal;
layout(location = 1) in float height01;
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

void main() {
    const vec3 n = normalize(normal);
    const vec3 key = normalize(vec3(-0.45, -0.55, 0.70));
    const vec3 fill = normalize(vec3(0.6, 0.3, 0.4));
    // Lit from both sides: the reflector is seen from above and, through the holder, below.
    const float light = 0.25 + 0.6 * abs(dot(n, key)) + 0.2 * abs(dot(n, fill));
    const vec3 base = pc.shade.z > 0.5 ? height_colour(height01) : vec3(0.72, 0.75, 0.80);
    colour = vec4(base * light, 1.0);
}
