// What one lighting evaluation produces, whichever backend traced it (the fast path on
// Vulkan or the CPU reference): the rays' fates, the stage times and the far fields.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "farfield/farfield.hpp"

namespace fird {

// Where the emitted rays went (DESIGN.md §2: emitted = discarded + direct + far field +
// lost, exactly, in rays; model/energy_balance.hpp turns it into lumens, where the
// reflector's reflectance adds the absorbed flux).
struct RayTally {
    std::uint64_t emitted = 0;
    std::uint64_t discarded = 0;
    std::uint64_t direct = 0;
    std::uint64_t farfield = 0;
    std::uint64_t lost = 0;
    std::uint64_t below_surface = 0;                // subset of lost: rays born inside the solid
    std::vector<std::uint64_t> by_reflections;      // far-field rays by reflection count
    std::vector<std::uint64_t> lost_by_reflections; // lost rays by the reflections they made
    double reflectance = 1.0;   // the reflector's: a ray keeps R^k of its flux after k
    bool direct_binned = false; // [trace] direct = "include": direct light is in the far field
};

struct StageTimings {
    double rayset_ms = 0.0;
    double heightfield_ms = 0.0;
    double trace_ms = 0.0;
    double histogram_ms = 0.0;
    double compare_ms = 0.0;
    double total_ms = 0.0;
};

// One bounce of the fast path's trace, summed over the batches (fird trace --profile).
struct BounceProfile {
    std::uint64_t rays = 0;            // rays walked in this bounce
    double trace_ms = 0.0;             // the trace pass (device time)
    double order_ms = 0.0;             // ordering the rays it reflected for the next bounce
    std::uint64_t steps = 0;           // quadtree nodes tested (the profiling pipeline's counts)
    std::uint64_t lane_steps = 0;      // steps the SIMD lanes paid: subgroup size x steps it ran
    std::uint64_t leaf_tests = 0;      // candidate texels tested against the surface
    std::uint64_t lane_leaf_tests = 0; // leaf tests the SIMD lanes paid, the same way
};

struct Evaluation {
    std::string device;
    std::string backend; // "cpu" or "gpu"
    RayTally tally;
    std::uint64_t rays_aborted = 0; // bounded device loops that ran out (counted as lost)
    double energy_per_ray_lm = 0.0;
    FarField farfield;
    std::optional<FarField> target_farfield;
    std::optional<double> l2_lm; // in `metric` (the scene's [optimize] metric)
    FarFieldMetric metric = FarFieldMetric::L2;
    StageTimings timings;
    std::vector<BounceProfile> bounces; // the fast path's, when profiled
    // Submissions (host waits) the fast evaluation made, when profiled: the trace's and,
    // with a target, the desired far field's and the compare's.
    std::optional<std::uint64_t> submissions;
    // vkAllocateMemory calls the evaluation made, when profiled.
    std::optional<std::uint64_t> device_memory_allocations;
};

} // namespace fird
