// fird tolerance across ranks: the realisations after the nominal one as the farm's shares.
// A request holds each realisation's kind and number (its draws follow from them and the
// run's seed, which every rank reads from the same command line); an answer its numbers
// (draws, surface RMS, l2, efficiency, peak intensity, beam angle, feasibility). The setup
// is the desired far field (or none), computed once on rank 0.
#pragma once

#include "distributed/batch_farm.hpp"
#include "tolerance/tolerance.hpp"

namespace fird::distributed {

// The hook for ToleranceRun::distributed.
DistributedRealisations tolerance_tracing(Farm& farm);

// A rank's side: its shares traced as run_tolerance traces them (trace_realisations).
ShareWorker tolerance_worker(const vk::Context& ctx, const Scene& scene, const ToleranceRun& run);

} // namespace fird::distributed
