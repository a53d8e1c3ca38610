#include "methods.hpp"

namespace fird {

StopReason run_grid(Objective& objective) {
    const ParameterSpace& space = objective.space();
    const std::uint64_t n = space.lattice_size();
    for (std::uint64_t i = 0; i < n; ++i)
        (void)objective(space.lattice_point(i));
    return StopReason::Exhausted;
}

} // namespace fird
