// The scene's light source for the rayset pass: shaders/emitter.h (the one definition of
// emission, shared with C++) read with this scene's parameters and emitter table.
#ifndef FIRD_SOURCE_GLSL
#define FIRD_SOURCE_GLSL

#include "common.glsl"

layout(std430, binding = kRaysetBindEmitterTable) readonly buffer EmitterTable {
    float emitter_table[];
};

#include "emitter.h"

// The scene's emitter (emitter.h), in the frame centred on the holder box.
Ray sample_source(vec4 u) {
    Emitter e;
    e.kind = kSourceKind;
    e.center = vec3(P.source_center[0], P.source_center[1], P.source_center[2]);
    e.axis = vec3(P.source_axis[0], P.source_axis[1], P.source_axis[2]);
    e.x_axis = vec3(P.source_x_axis[0], P.source_x_axis[1], P.source_x_axis[2]);
    e.length_mm = P.source_length;
    e.radius_mm = P.source_radius;
    e.width_mm = P.source_width;
    e.height_mm = P.source_height;
    e.table_c = P.source_table_c;
    e.table_g = P.source_table_g;
    const Emission m = sample_emitter(e, u);
    Ray r;
    r.origin = vec4(m.origin, 0.0);
    r.direction = vec4(m.direction, 0.0);
    return r;
}

// Ray i of the batch of a ray file (kSourceRayFile): the host read and placed it.
Ray ray_file_ray(uint i) {
    const uint at = kRayFileFloats * i;
    Ray r;
    r.origin = vec4(emitter_table[at], emitter_table[at + 1u], emitter_table[at + 2u], 0.0);
    r.direction = vec4(emitter_table[at + 3u], emitter_table[at + 4u], emitter_table[at + 5u], 0.0);
    return r;
}

#endif
