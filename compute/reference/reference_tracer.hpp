// The accuracy oracle: a double-precision CPU tracer against the true surface
// (DESIGN.md §1). Multi-threaded over rays; results do not depend on the thread count.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "farfield/farfield.hpp"
#include "model/evaluation_result.hpp"
#include "model/scene.hpp"
#include "model/source.hpp"
#include "model/surface.hpp"

namespace fird {

enum class RayFate { Discarded, Direct, FarField, Lost, BelowSurface };

struct PathResult {
    RayFate fate = RayFate::Discarded;
    std::uint32_t reflections = 0;
    glm::dvec3 direction{0.0}; // outgoing direction (FarField)
};

// The reflector's finish as one ray meets it: the material and the ray's draws (the
// counter-based stream of its emission index under the seed: shaders/material.h).
struct RayFinish {
    MaterialDesc material;
    std::uint64_t seed = 1;
    std::uint64_t index = 0;
};

// One ray through the reflector with up to max_bounces reflections (a perfect mirror
// without `finish`). `vertices`, when given, receives the path's points (origin, hits, and
// an end point).
PathResult trace_path(const Surface& surface, const Holder& holder, const Ray& ray,
                      std::uint32_t max_bounces, BouncePolicy policy,
                      std::vector<glm::dvec3>* vertices = nullptr,
                      const RayFinish* finish = nullptr);

struct ReferenceResult {
    RayTally tally;
    FarField farfield;
    double energy_per_ray_lm = 0.0;
    double trace_ms = 0.0;
    unsigned threads = 0;
};

struct ReferenceOptions {
    std::uint64_t rays = 0;
    std::uint64_t seed = 1;
    SamplerKind sampler = SamplerKind::Stratified;
    std::uint32_t max_bounces = 1;
    BouncePolicy bounce_policy = BouncePolicy::Paper;
    std::uint32_t farfield_w = 1800;
    std::uint32_t farfield_h = 900;
    unsigned threads = 0;  // 0: all hardware threads
    MaterialDesc material; // the reflector's finish
    DirectLight direct = DirectLight::Exclude;
};

// Emits `rays` rays from the source and traces them against the reflector.
ReferenceResult trace_reference(const SourceDesc& source, const Surface& surface,
                                const ReferenceOptions& options);

} // namespace fird
