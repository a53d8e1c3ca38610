#version 450
// The draw command's texture (the font atlas, or a view FIRD drew) times the vertex colour.
layout(binding = 0) uniform sampler2D image;
layout(location = 0) in vec2 frag_uv;
layout(location = 1) in vec4 frag_colour;
layout(location = 0) out vec4 colour;

void main() { colour = frag_colour * texture(image, frag_uv); }
