#version 450
// The reflector straight from the device height field: one vertex per (decimated) texel,
// its height and gradient read as vertex attributes from the buffers the trace uses;
// x and y from the texel's index (gl_VertexIndex is the texel number).
layout(location = 0) in float height;
layout(location = 1) in vec2 gradient;
layout(push_constant) uniform Push {
    mat4 view_projection;
    vec4 grid;   // holder min x, min y, texel width, texel depth (mm)
    vec4 shade;  // z low, z high, colour mode (0 metal, 1 height, 2 slope), the heights' origin z
    uvec4 size;  // height field width, height
} pc;
layout(location = 0) out vec3 normal;
layout(location = 1) out float height01;

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
    gl_Position = pc.view_projection * vec4(p, 1.0);
}
