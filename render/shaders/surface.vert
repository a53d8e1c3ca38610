#version 450
// The reflector straight from the device height field: one vertex per (decimated) texel,
// its height and gradient read as vertex attributes from the buffers the trace uses;
// x and y from the texel's index (gl_VertexIndex is the texel number).
layout(location = 0) in float height;
layout(location = 1) in vec2 gradient;
layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 grid;   // holder min x, min y, texel width, texel depth (mm)
    // Colour scale's low and high end (heights in mm; curvature: log10 of 1/mm), colour mode
    // (0 metal, 1 height, 2 slope, 3 curvature), the heights' origin z.
    vec4 shade;
    uvec4 size;  // height field width, height
} pc;
layout(location = 0) out vec3 normal;
layout(location = 1) out float height01;
// For the curvature colours: the gradient and the press-plane point, interpolated across
// each triangle so that the fragment shader differentiates one against the other.
layout(location = 2) out vec2 slope_gradient;
layout(location = 3) out vec2 plane_mm;

void main() {
    const uint i = uint(gl_VertexIndex) % pc.size.x;
    const uint j = uint(gl_VertexIndex) / pc.size.x;
    const vec3 p = vec3(pc.grid.x + (float(i) + 0.5) * pc.grid.z,
                        pc.grid.y + (float(j) + 0.5) * pc.grid.w, height + pc.shade.w);
    normal = normalize(vec3(-gradient, 1.0));
    height01 = pc.shade.z > 1.5
                   // The slope from the press plane, 0 .. 90 degrees.
                   ? atan(length(gradient)) / 1.5707963
                   : clamp((p.z - pc.shade.x) / max(pc.shade.y - pc.shade.x, 1e-6), 0.0, 1.0);
    slope_gradient = gradient;
    plane_mm = p.xy;
    gl_Position = pc.view_projection * vec4(p, 1.0);
}
