#include <cmath>

#include "methods.hpp"

namespace fird {

namespace {

// The lattice neighbour of `centre` moved by `moves` (parameter, +-1 step); false when it
// leaves the box.
bool neighbour(const ParameterSpace& space, const std::vector<double>& centre,
               std::initializer_list<std::pair<std::size_t, double>> moves,
               std::vector<double>& out) {
    out = centre;
    for (const auto& [k, dir] : moves) {
        out[k] = centre[k] + dir * space.step[k];
        if (out[k] < space.lo[k] - 1e-9 * space.step[k] ||
            out[k] > space.hi[k] + 1e-9 * space.step[k])
            return false;
    }
    out = space.snap(out);
    return true;
}

} // namespace

std::vector<std::vector<double>> lattice_neighbours(const ParameterSpace& space,
                                                    const std::vector<double>& centre,
                                                    const std::vector<bool>& free, bool diagonal) {
    std::vector<std::vector<double>> out;
    std::vector<double> x;
    for (std::size_t k = 0; k < space.size(); ++k)
        if (free[k])
            for (double dir : {-1.0, 1.0})
                if (neighbour(space, centre, {{k, dir}}, x)) out.push_back(x);
    if (diagonal)
        for (std::size_t i = 0; i < space.size(); ++i)
            for (std::size_t j = i + 1; j < space.size(); ++j)
                if (free[i] && free[j])
                    for (double di : {-1.0, 1.0})
                        for (double dj : {-1.0, 1.0})
                            if (neighbour(space, centre, {{i, di}, {j, dj}}, x)) out.push_back(x);
    return out;
}

StopReason run_lattice_descent(Objective& objective, const std::vector<double>& x0,
                               const std::vector<bool>& free, bool diagonal) {
    const ParameterSpace& space = objective.space();
    std::vector<double> centre = space.snap(x0);
    double centre_l2 = objective(centre);
    // Each round polls every neighbour before moving (a complete poll): with noisy l2,
    // moving to the first improvement would follow the noise more often.
    const std::uint64_t rounds = space.lattice_size();
    for (std::uint64_t round = 0; round < rounds; ++round) {
        std::vector<double> best = centre;
        double best_l2 = centre_l2;
        const auto poll = [&](const std::vector<std::vector<double>>& points) {
            for (const std::vector<double>& x : points) {
                const double l2 = objective(x);
                if (l2 < best_l2) best = x, best_l2 = l2;
            }
        };
        poll(lattice_neighbours(space, centre, free, false));
        // Correlated parameters (a focal length and the vertex height, say) improve only
        // together: where no single step helps, try the steps of two at once.
        if (best == centre && diagonal) {
            const auto all = lattice_neighbours(space, centre, free, true);
            const std::size_t singles = lattice_neighbours(space, centre, free, false).size();
            poll({all.begin() + std::ptrdiff_t(singles), all.end()});
        }
        if (best == centre) return StopReason::Converged;
        centre = best;
        centre_l2 = best_l2;
    }
    return StopReason::Converged; // a strict descent cannot revisit: bounded by the lattice
}

} // namespace fird
