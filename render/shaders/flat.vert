#version 450
// Coloured triangles in normalized device coordinates, transformed by one matrix.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec4 in_colour;
layout(location = 0) out vec4 colour;
layout(push_constant) uniform Push { mat4 transform; } pc;

void main() {
    colour = in_colour;
    gl_Position = pc.transform * vec4(in_position, 1.0);
}
