// Where a search begins (fird optimize --start): the scene's reflector, or a profile
// tailored to the desired far field (optimize/tailored_start.hpp) put on the search's
// lattice, each edge-ray design traced once quickly and the closer one kept.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "farfield/farfield.hpp"
#include "optimize/search.hpp"
#include "optimize/search_types.hpp"
#include "vk/context.hpp"

namespace fird {

// Why the scene cannot start from a tailored profile (one line), or nothing when it can:
// the profile family with at least one free height h_<k>.
std::optional<std::string> tailored_start_refusal(const Scene& scene);

struct SearchStartPoint {
    std::vector<double> x; // in the parameter space's order
    StartReport report;
};

// The tailored start of the scene's search against `desired` (on the scene's grid): the
// point source at the source's centre, the apex where the scene's reflector has it (z0 +
// h_0), the heights the curve gives at the profile's radii clamped into their bounds and
// snapped to their steps (the other parameters as the scene has them). Both edge rays are
// solved; each that has an answer is traced once at the search's first stage fidelity
// (rays of a stream of its own) and the lower metric kept. Throws std::invalid_argument
// (one line) when neither has an answer or the scene cannot be tailored.
SearchStartPoint tailored_start(const vk::Context& ctx, const Scene& scene, const FarField& desired,
                                const SearchSettings& settings);

// A search request (its settings set) made to begin at the tailored start, as
// `fird optimize --start tailored` and the workbench begin one: the desired far field the
// search will chase (search_desired), the start, its report with the named parameters and
// the time the tailoring took. Throws as tailored_start.
void set_tailored_start(const vk::Context& ctx, const Scene& scene, SearchRequest& request);

} // namespace fird
