// fird calibrate rays across ranks: a Table 1 row's runs, in pairs (the replicate estimate
// needs both far fields of a pair, so a pair never splits), as the farm's shares. A request
// holds the row's count index and the pairs' first runs (the seeds follow from them and
// the seed every rank reads from the same command line); an answer each pair's l2s and the
// l2 between its two far fields. The setup is the desired far field (traced on rank 0 at
// ten times the largest count, once).
#pragma once

#include "calibrate/calibration.hpp"
#include "distributed/batch_farm.hpp"

namespace fird::distributed {

// The hook for RaysTableOptions::distributed.
DistributedRuns calibration_tracing(Farm& farm);

// A rank's side: its pairs traced as calibrate_rays traces them (trace_run_pairs), with an
// evaluator kept while the row stays the same.
ShareWorker calibration_worker(const vk::Context& ctx, const Scene& scene,
                               const RaysTableOptions& options);

} // namespace fird::distributed
