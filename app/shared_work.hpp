// A command's work with its batches shared among the ranks of an MPI job (a build with
// FIRD_BUILD_MPI): how a lost rank ends it, and the note on what was exchanged.
#pragma once

#if FIRD_HAVE_MPI
#include <cstdio>
#include <optional>

#include "distributed/batch_farm.hpp"
#include "optimize/search_types.hpp"

namespace fird::app {

// Runs `work` (it returns its elapsed seconds), whose batches `farm` may share among ranks. A
// lost rank ends it: rethrown (main prints its one line), or the exit code 1 where the SIGTERM
// handler already wrote that line (the process may not live to write it again). Then the
// farm's note on stderr, `items` naming what was shared. nullopt: the work ran to its end.
template <class Work>
std::optional<int> run_shared(const std::optional<distributed::Farm>& farm,
                              const SearchControl& control, const char* items, Work&& work) {
    double elapsed_s = 0.0;
    try {
        elapsed_s = work();
    } catch (const distributed::RankLost&) {
        if (control.noted.load()) return 1;
        throw;
    }
    if (farm) std::fprintf(stderr, "fird: note: %s\n", farm->summary(elapsed_s, items).c_str());
    return std::nullopt;
}

} // namespace fird::app
#endif
