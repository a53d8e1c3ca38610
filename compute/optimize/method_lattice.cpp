#include <cmath>

#include "methods.hpp"

namespace fird {

StopReason run_lattice_descent(Objective& objective, const std::vector<double>& x0,
                               const std::vector<bool>& free) {
    const ParameterSpace& space = objective.space();
    std::vector<double> centre = space.snap(x0);
    double centre_l2 = objective(centre);
    // Each round polls every neighbour before moving (a complete poll): with noisy l2,
    // moving to the first improvement would follow the noise more often.
    const std::uint64_t rounds = space.lattice_size();
    for (std::uint64_t round = 0; round < rounds; ++round) {
        std::vector<double> best = centre;
        double best_l2 = centre_l2;
        for (std::size_t k = 0; k < space.size(); ++k) {
            if (!free[k]) continue;
            for (double dir : {-1.0, 1.0}) {
                std::vector<double> x = centre;
                x[k] = centre[k] + dir * space.step[k];
                if (x[k] < space.lo[k] - 1e-9 * space.step[k] ||
                    x[k] > space.hi[k] + 1e-9 * space.step[k])
                    continue;
                x = space.snap(x);
                const double l2 = objective(x);
                if (l2 < best_l2) best = x, best_l2 = l2;
            }
        }
        if (best == centre) return StopReason::Converged;
        centre = best;
        centre_l2 = best_l2;
    }
    return StopReason::Converged; // a strict descent cannot revisit: bounded by the lattice
}

} // namespace fird
