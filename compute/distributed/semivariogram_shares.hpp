// fird calibrate semivariogram across ranks: the series' points (each the desired reflector
// with one parameter moved, traced with its own rays) as the farm's shares. A request holds
// the points (parameter, value, seed); an answer each point's l2. The setup is the desired
// far field (traced on rank 0, once). The noise replicates and the resolvable step's
// probes stay on rank 0.
#pragma once

#include "calibrate/calibration.hpp"
#include "distributed/batch_farm.hpp"

namespace fird::distributed {

// The hook for SemivariogramOptions::distributed.
DistributedSeries semivariogram_tracing(Farm& farm);

// A rank's side: its points traced as calibrate_semivariogram traces them
// (trace_series_points), with one evaluator at the semivariogram's rays.
ShareWorker semivariogram_worker(const vk::Context& ctx, const Scene& scene,
                                 const SemivariogramOptions& options);

} // namespace fird::distributed
