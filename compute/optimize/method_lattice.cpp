#include <cmath>

#include "methods.hpp"

namespace fird {

namespace {

// The lattice neighbour of `centre` moved by `moves` (parameter, +-1 step); false when it
// leaves the box.
bool neighbour(const ParameterSpace& space, const std::vector<double>& centre,
               const std::vector<std::pair<std::size_t, double>>& moves, std::vector<double>& out) {
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

std::size_t lattice_moves_together(std::size_t free_parameters) {
    // Triples: C(n, 3) * 8 points, 8 for Model A's three parameters and 32 for the four of
    // B and C; beyond five parameters (80) they would outnumber everything else polled.
    return free_parameters <= 5 ? 3 : 2;
}

std::vector<std::vector<double>> lattice_neighbours(const ParameterSpace& space,
                                                    const std::vector<double>& centre,
                                                    const std::vector<bool>& free,
                                                    std::size_t together) {
    std::vector<std::size_t> params;
    for (std::size_t k = 0; k < space.size(); ++k)
        if (free[k]) params.push_back(k);
    std::vector<std::vector<double>> out;
    std::vector<double> x;
    // Every set of `size` free parameters (in lexicographic order), each stepped -1 or +1
    // (the first parameter's sign varying slowest): all singles, then all pairs, then all
    // triples.
    for (std::size_t size = 1; size <= together && size <= params.size(); ++size) {
        std::vector<std::size_t> pick(size);
        for (std::size_t i = 0; i < size; ++i)
            pick[i] = i;
        while (true) {
            for (std::uint32_t signs = 0; signs < (1u << size); ++signs) {
                std::vector<std::pair<std::size_t, double>> moves;
                for (std::size_t i = 0; i < size; ++i)
                    moves.emplace_back(params[pick[i]],
                                       (signs >> (size - 1 - i)) & 1u ? 1.0 : -1.0);
                if (neighbour(space, centre, moves, x)) out.push_back(x);
            }
            // The next set: the rightmost index that can move, and those after it.
            std::size_t i = size;
            while (i > 0 && pick[i - 1] == params.size() - size + i - 1)
                --i;
            if (i == 0) break;
            ++pick[i - 1];
            for (std::size_t j = i; j < size; ++j)
                pick[j] = pick[j - 1] + 1;
        }
    }
    return out;
}

StopReason run_lattice_descent(Objective& objective, const std::vector<double>& x0,
                               const std::vector<bool>& free, std::size_t together) {
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
            // Several per submission (Objective::evaluate_all), judged in order.
            const std::vector<double> l2s = objective.evaluate_all(points);
            for (std::size_t k = 0; k < points.size(); ++k)
                if (l2s[k] < best_l2) best = points[k], best_l2 = l2s[k];
        };
        // Correlated parameters (a focal length and the vertex height, say) improve only
        // together: where no single step helps, try the steps of two at once, then of three
        // (Model A's focus and vertex move as (+1, +1, -1) between two lattice basins).
        std::size_t polled = 0;
        for (std::size_t size = 1; size <= together && best == centre; ++size) {
            const auto all = lattice_neighbours(space, centre, free, size);
            poll({all.begin() + std::ptrdiff_t(polled), all.end()});
            polled = all.size();
        }
        if (best == centre) return StopReason::Converged;
        centre = best;
        centre_l2 = best_l2;
    }
    return StopReason::Converged; // a strict descent cannot revisit: bounded by the lattice
}

} // namespace fird
