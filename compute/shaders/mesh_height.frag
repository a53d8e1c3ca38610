#version 450
// Writes the height (clamped to the holder's z range, as the analytic families are)
// and the face's gradient, zero where the height was clamped (a plateau).
#extension GL_GOOGLE_include_directive : require
#include "fird_shared.h"

layout(location = 0) in float height_mm;
layout(location = 1) flat in vec2 face_gradient;
layout(push_constant) uniform Push { MeshRasterPush pc; };
layout(location = 0) out float out_height;
layout(location = 1) out vec2 out_gradient;

void main() {
    const bool plateau = height_mm <= pc.holder_min[2] || height_mm >= pc.holder_max[2];
    out_height = clamp(height_mm, pc.holder_min[2], pc.holder_max[2]);
    out_gradient = plateau ? vec2(0.0) : face_gradient;
}
