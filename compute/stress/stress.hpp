// fird stress: the fast path's numerical stability, case by case, against the CPU
// reference on the same rays — grazing rays, texel corners and edges, axis-parallel rays,
// steep walls, every family and a mesh, both hit modes and bounce policies, extreme
// height-field shapes and sizes, tiny and huge scenes, scenes far from the origin.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/scene.hpp"
#include "model/source.hpp"
#include "vk/context.hpp"

namespace fird {

struct StressCase {
    std::string name;
    Scene scene;
    std::vector<Ray> rays;       // traced as given (empty: the scene's own effective rays)
    std::uint32_t sample = 2000; // rays drawn from the source when `rays` is empty
    // p99 of the first hits' xy error: the refined surface is the bilinear patch through
    // the true surface's corner heights, so a hit moves by that patch's height error over
    // the ray's slope; 0.25 texel bounds it for every case whose rays meet the surface at
    // more than ~0.01 rad (cases with grazing rays state their own).
    double hit_tolerance_texels = 0.25;
    // A leaving direction's error, ray by ray, over every ray that reflected on either
    // side: the refined mode reflects about the true gradient at its hit, so a
    // once-reflected ray errs by twice the curvature times the hit's displacement
    // (~1e-5 rad here); each further bounce multiplies that, and 0.05 rad bounds it for
    // every case up to 6 bounces. Rays past it (their fate differs, or a kink lies between
    // the two hits) may be at most kMaxDirectionOutliers of the case (stress.cpp).
    double direction_tolerance_rad = 0.05;
    // Compare against the reference surface at all (false where the height field cannot
    // resolve the surface, e.g. one texel across: then only stability is asked).
    bool compare_surface = true;
    // Compare whole multi-bounce paths (false for the paper hit mode, whose flat-topped
    // columns reflect differently from the exact surface by design).
    bool compare_paths = true;
    std::string note; // why a comparison is relaxed or left out
};

struct StressResult {
    std::string name;
    std::uint64_t rays = 0;
    std::uint64_t aborted = 0;           // bounded loops that ran out
    std::uint64_t nonfinite = 0;         // NaN or Inf in hits, paths or the far field
    std::uint64_t tunnelled = 0;         // the reference hits the surface, the fast path misses it
    std::uint64_t spurious = 0;          // the fast path hits where the reference finds nothing
    std::uint64_t extra_reflections = 0; // paths with more reflections than the reference's
    std::uint64_t missing_reflections = 0; // paths with fewer reflections than the reference's
    // Of those four, the rays whose parting hit lies within the clamp band (stress.cpp).
    std::uint64_t mismatches_near_clamp = 0;
    double hit_error_p99_texels = 0.0;
    double hit_error_max_texels = 0.0;
    // Leaving directions of every path that reflected on either side (also those whose
    // reflection counts differ: a mismatch shows here as well as in the counts).
    double direction_error_p99_rad = 0.0;
    double direction_error_max_rad = 0.0;
    std::uint64_t direction_outliers = 0; // directions off by more than the case's tolerance
    bool energy_balanced = true;
    bool ok = true;
    std::string failure; // why not, in one line
    std::string note;    // the case's relaxations
};

// The suite (scenes built in code: no file of the source tree is needed).
std::vector<StressCase> stress_cases(const vk::Context& ctx, const std::string& scratch_dir);

StressResult run_stress_case(const vk::Context& ctx, const StressCase& c);

nlohmann::json stress_json(const std::vector<StressResult>& results);
std::string stress_table(const std::vector<StressResult>& results);

} // namespace fird
