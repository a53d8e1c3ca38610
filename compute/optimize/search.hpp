// One reflector search (fird optimize): the desired far field computed once, the start
// evaluated, the method run through the Objective, and the best re-evaluated with fresh
// rays at the scene's fidelity beside the noise floor.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "evaluation/desired_farfield.hpp"
#include "optimize/search_types.hpp"
#include "vk/context.hpp"

namespace fird {

struct SearchRequest {
    SearchSettings settings;
    SearchControl* control = nullptr; // may be null
    std::vector<Candidate> replay;    // a resumed search's recorded candidates
    CandidateCallback on_candidate;   // may be empty
    // A desired far field given directly, on the scene's far-field grid, instead of the
    // scene's [target]: one computed by another tracer (the CPU reference) or from an
    // analytic answer, so that a search can be judged by something other than the fast
    // path that traces its candidates. The scene then needs no [target] (a target reflector
    // there still gives surface_rms_mm).
    std::optional<DesiredFarField> desired;
    // Where the search starts instead of the scene's reflector (the space's order; fird
    // optimize --start tailored), and how it was found (copied into SearchResult::start).
    // A relative photometric target is still scaled to the scene's reflector's flux
    // (search_desired), so searches from different starts chase the same far field.
    std::optional<std::vector<double>> start;
    StartReport start_report;
};

struct SearchOutcome {
    SearchResult result;
    DesiredFarField desired;               // on the scene's grid
    std::optional<FarField> best_farfield; // the best, fresh rays, scene fidelity
};

// The desired far field run_search chases when the request gives none: the scene's
// [target], a relative photometric one scaled to the far-field flux of the scene's reflector
// traced at the scene's fidelity with the search's final stream of rays.
DesiredFarField search_desired(const vk::Context& ctx, const Scene& scene,
                               const SearchSettings& settings);

SearchOutcome run_search(const vk::Context& ctx, const Scene& scene, const SearchRequest& request);

// Whether a search of the scene runs a population (pagmo's CMA-ES or xNES): --method cmaes
// or xnes, or auto beyond a handful of free parameters (methods.hpp, kPopulationAbove).
bool searches_with_population(const Scene& scene, const SearchSettings& settings);

// Loads the population searches' module (libfird_pagmo.so) now, so that a program without
// it fails before anything is traced or written: std::runtime_error in one line naming it.
void require_population_module();

// The stages' fidelities: `auto` one per ray count (coarser far fields for all but the
// last, which is the scene's grid), the other methods one at the last count.
std::vector<Fidelity> search_stages(const Scene& scene, const SearchSettings& settings);

// The seed of stream `stream` of a search seeded `seed`: a Philox4x32-10 block keyed by the
// seed at a counter holding the stream (DESIGN.md §2: a counter-based generator, not XOR-ed
// hashes), never equal to `avoid` (the target reflector's seed).
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream, std::uint64_t avoid);
// The seed no stream of a search takes: the target reflector's (a candidate traced with the
// target's own rays would match it noise and all); none for other targets.
std::uint64_t streams_avoid(const Scene& scene);

// The coarsest grid whose cells are blocks of the scene's and that has no more cells than
// rays / 20 (so a stage's histogram is not mostly counting noise); the scene's own grid
// when no block size divides both sides.
std::pair<std::uint32_t, std::uint32_t> stage_farfield(std::uint32_t width, std::uint32_t height,
                                                       std::uint64_t rays);

} // namespace fird
