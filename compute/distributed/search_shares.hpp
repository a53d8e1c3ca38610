// fird optimize across ranks: a search's batches (Objective::evaluate_all's points) as the
// farm's shares. A request holds the stage's fidelity (rays, seed, grids), the backend and
// the share's parameter vectors; an answer three numbers per point (l2, far-field flux,
// wall time). The setup is the desired far field: computed once on rank 0 and sent once to
// each rank (each rank would otherwise trace the start and the target again, and on another
// kind of device might not get the very same numbers).
#pragma once

#include "distributed/batch_farm.hpp"
#include "optimize/point_trace.hpp"
#include "optimize/search_types.hpp"

namespace fird::distributed {

// The hook for SearchSettings::distributed.
DistributedTrace search_tracing(Farm& farm, Backend backend);

// A rank's side: its shares traced by `tracer`.
ShareWorker search_worker(PointTracer& tracer);

} // namespace fird::distributed
