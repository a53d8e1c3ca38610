// A ray picked by its identity, its index in the scene's rayset (ray i of scene.trace.rays
// emitted under scene.trace.seed: the counter-based generator keys it by (seed, index),
// so the same index is the same ray whatever the batch, the thread or the other rays
// traced beside it), re-traced alone through the reflector already on the device: its
// path and its RQRM walk, step by step, without tracing the far field again.
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "fastpath/fast_tracer.hpp"
#include "fastpath/walk_step.hpp"
#include "model/source.hpp"

namespace fird {

struct PickedRay {
    std::uint64_t index = 0; // in the rayset
    Ray ray;                 // as emitted
    RayPath path;
    std::vector<WalkStep> walk; // every bounce's, in order
};

// Ray `index` of `scene`'s rayset as emitted. Throws std::invalid_argument, one line
// naming the index, when it is past the rays emitted or a ray the holder discards (it
// never meets the holder box, so it is never traced).
Ray effective_ray(const Scene& scene, std::uint64_t index);

// The ray `index` of `scene`'s rayset (its source, sampler, seed and rays) traced alone
// with `tracer`'s current reflector (throws as effective_ray).
PickedRay trace_picked_ray(FastTracer& tracer, const Scene& scene, std::uint64_t index);

// {"index", "origin_mm", "direction", "path_mm" (its vertices: origin, hits, exit),
//  "reflections", "walk" (walk_json)} (docs/workbench.md).
nlohmann::json picked_ray_json(const PickedRay& picked);

} // namespace fird
