// libfird_pagmo.so: pagmo2's CMA-ES (Hansen) and xNES (Glasmachers et al.), not written
// here, one generation a call (pagmo_generations.hpp). The one file that sees pagmo's
// headers (with Boost's and Eigen's); method_population.cpp drives it.
#include <memory>
#include <utility>
#include <variant>

#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/xnes.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/types.hpp>

#include "fird_module_stamp.h"
#include "optimize/pagmo_generations.hpp"

namespace fird {
namespace {

// The pagmo problem (a user-defined problem: fitness and bounds): each fitness is FIRD's.
// pagmo copies the problem with the population, so the callback is shared.
struct CallbackProblem {
    std::shared_ptr<const PagmoFitness> callback;
    std::vector<double> lo, hi;

    pagmo::vector_double fitness(const pagmo::vector_double& c) const { return {(*callback)(c)}; }
    std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return {lo, hi}; }
};

using Algorithm = std::variant<pagmo::cmaes, pagmo::xnes>;

struct Run {
    Algorithm algorithm;
    pagmo::population population;
};

void* create(const PagmoRunSpec& spec, PagmoFitness fitness) {
    // One generation per evolve(), the memory kept between them; pagmo's own stops (ftol,
    // xtol) off, since with gen = 1 they would end a call before its generation is
    // evaluated, unseen: the convergence rule is FIRD's (method_population.cpp).
    Algorithm algorithm =
        spec.xnes
            ? Algorithm(pagmo::xnes(1, -1, -1, -1, spec.sigma0, 0.0, 0.0, true, false, spec.seed))
            : Algorithm(
                  pagmo::cmaes(1, -1, -1, -1, -1, spec.sigma0, 0.0, 0.0, true, false, spec.seed));
    CallbackProblem problem{.callback = std::make_shared<const PagmoFitness>(std::move(fitness)),
                            .lo = spec.lo,
                            .hi = spec.hi};
    auto run = std::make_unique<Run>(
        Run{.algorithm = std::move(algorithm),
            .population = pagmo::population(pagmo::problem(std::move(problem)), 0u, spec.seed)});
    return run.release();
}

Run& as_run(void* run) {
    return *static_cast<Run*>(run);
}

void push_back(void* run, const std::vector<double>& c, double fitness) {
    as_run(run).population.push_back(c, {fitness});
}

void evolve_copy(void* run) {
    Algorithm copy = as_run(run).algorithm;
    const auto& population = as_run(run).population;
    std::visit([&](auto& algorithm) { (void)algorithm.evolve(population); }, copy);
}

void evolve(void* run) {
    Run& r = as_run(run);
    r.population =
        std::visit([&](auto& algorithm) { return algorithm.evolve(r.population); }, r.algorithm);
}

void destroy(void* run) {
    delete static_cast<Run*>(run);
}

constexpr PagmoGenerations kGenerations{.stamp = FIRD_MODULE_STAMP,
                                        .create = create,
                                        .push_back = push_back,
                                        .evolve_copy = evolve_copy,
                                        .evolve = evolve,
                                        .destroy = destroy};

} // namespace
} // namespace fird

// The module's one entry point (looked up by name: io/program_files.hpp).
extern "C" __attribute__((visibility("default"))) const fird::PagmoGenerations*
fird_pagmo_generations() {
    return &fird::kGenerations;
}
