#version 450
// Dear ImGui's vertices (pixel positions, texture coordinates, RGBA8 colour) to clip space.
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in vec4 colour;
layout(push_constant) uniform Push {
    vec2 scale;
    vec2 translate;
} pc;
layout(location = 0) out vec2 frag_uv;
layout(location = 1) out vec4 frag_colour;

void main() {
    frag_uv = uv;
    frag_colour = colour;
    gl_Position = vec4(position * pc.scale + pc.translate, 0.0, 1.0);
}
