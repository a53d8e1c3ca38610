// Light sources: emission sampling (position on the emitter, direction) and the test of
// whether a ray can meet the holder box at all (DESIGN.md §2).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "emitter.h"
#include "scene.hpp"

namespace fird {

struct Ray {
    glm::dvec3 origin;
    glm::dvec3 direction; // unit length
};

// A disk's or rectangle's local +x where the scene gives none: world +x made perpendicular
// to the normal, or world +y where the normal lies within 26 degrees of the x axis.
glm::dvec3 default_x_axis(const glm::dvec3& normal);

// Whether the source has an axis to tilt ([source.optimize], tolerances): every kind but a
// sphere and an isotropic point.
bool source_has_axis(const SourceDesc& source);

// The source as shaders/emitter.h's emitter (the one definition of its sampling), in a
// frame whose origin is `origin` (the fast path's is the holder box's centre).
gpu::emission::Emitter emitter_of(const SourceDesc& source, const glm::dvec3& origin = {});

// Maps four uniforms in (0, 1) to an emitted ray: shaders/emitter.h's sample_emitter (which
// says how each emitter samples), in double.
Ray sample_source(const SourceDesc& source, const std::array<double, 4>& u);

// The uniforms for ray `index` of the `rays` emitted, keyed by seed: Philox stratified in
// its first two dimensions (sampling/strata.hpp), independent Philox, or scrambled Sobol.
std::array<double, 4> ray_uniforms(SamplerKind sampler, std::uint64_t seed, std::uint64_t index,
                                   std::uint64_t rays);

// Ray `index` of the `rays` emitted under `seed`: sampled from the uniforms, or for a ray
// file read from the file (model/ray_file_source.hpp; the sampler does not apply).
Ray emit_ray(const SourceDesc& source, SamplerKind sampler, std::uint64_t seed, std::uint64_t index,
             std::uint64_t rays);

// K of the scene's effective rays, spread evenly over its emission order: rays the fast
// path's rayset holds too (the same counter-based stream), for paths shown or exported.
// A ray's identity is its index in that order (ray i of scene.trace.rays under the seed).
std::vector<std::uint64_t> sample_effective_ray_indices(const Scene& scene, std::uint32_t k);
std::vector<Ray> sample_effective_rays(const Scene& scene, std::uint32_t k);

// True when the forward half-line (t >= 0) meets the closed holder box.
bool ray_meets_box(const Ray& ray, const Holder& holder);

// [t_enter, t_exit] of the forward half-line inside the box; false when it misses.
bool clip_to_box(const Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi, double& t_enter,
                 double& t_exit);

} // namespace fird
