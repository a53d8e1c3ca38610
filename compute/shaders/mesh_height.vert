#version 450
// The paper's z-buffer step (§4.2): a height-field mesh seen orthographically from
// above. x, y map the holder rectangle onto the height texture; depth orders the
// surfaces so the highest wins (compare GREATER); the exact height and the triangle's
// gradient go to colour attachments.
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(location = 0) in vec3 position_mm;
layout(location = 1) in vec2 gradient;
layout(push_constant) uniform Push { MeshRasterPush pc; };
layout(location = 0) out float height_mm;
layout(location = 1) flat out vec2 face_gradient;

void main() {
    const vec2 lo = vec2(pc.holder_min[0], pc.holder_min[1]);
    const vec2 hi = vec2(pc.holder_max[0], pc.holder_max[1]);
    const vec2 ndc = 2.0 * (position_mm.xy - lo) / (hi - lo) - 1.0;
    const float depth = (position_mm.z - pc.depth_z0_mm) / (pc.depth_z1_mm - pc.depth_z0_mm);
    gl_Position = vec4(ndc, depth, 1.0);
    height_mm = position_mm.z;
    face_gradient = gradient;
}
