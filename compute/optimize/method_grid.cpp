#include <algorithm>

#include "methods.hpp"

namespace fird {

StopReason run_grid(Objective& objective) {
    const ParameterSpace& space = objective.space();
    const std::uint64_t n = space.lattice_size();
    // In chunks, several candidates per submission (Objective::evaluate_all).
    constexpr std::uint64_t chunk = 64;
    for (std::uint64_t first = 0; first < n; first += chunk) {
        std::vector<std::vector<double>> points;
        for (std::uint64_t i = first; i < std::min(n, first + chunk); ++i)
            points.push_back(space.lattice_point(i));
        (void)objective.evaluate_all(points);
    }
    return StopReason::Exhausted;
}

} // namespace fird
