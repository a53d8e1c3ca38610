// The scene's light source for the rayset pass: shaders/emitter.h (the one definition of
// emission, shared with C++) read with this scene's parameters and emitter table.
#ifndef FIRD_SOURCE_GLSL
#define FIRD_SOURCE_GLSL

#include "common.glsl"

// Through an R32F texel view: the sampling's binary search and a ray file's rays are loads
// at per-lane indices, which CPU drivers run lane by lane from a storage buffer, where an
// image load is one gather (docs/architecture.md, "Far fields as texels").
layout(binding = kRaysetBindEmitterTable, r32f) uniform readonly imageBuffer emitter_table;
#define FIRD_TABLE_AT(k) imageLoad(emitter_table, int(k)).r

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
    r.origin = vec4(FIRD_TABLE_AT(at), FIRD_TABLE_AT(at + 1u), FIRD_TABLE_AT(at + 2u), 0.0);
    r.direction = vec4(FIRD_TABLE_AT(at + 3u), FIRD_TABLE_AT(at + 4u), FIRD_TABLE_AT(at + 5u), 0.0);
    return r;
}

#endif
