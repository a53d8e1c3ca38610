// A search's batches traced across the ranks of an MPI job: rank 0 runs the search and
// hands each other rank a share of every batch (Objective::evaluate_all's points); the
// other ranks trace their shares with the same stage, seed and desired far field and send
// back only numbers. What crosses the network: per batch, the stage's fidelity and the
// points' parameter vectors out, three numbers per point back; once per run, the desired
// far field (each rank would otherwise trace the start and the target again, and on other
// devices might not get the very same numbers).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "distributed/job.hpp"
#include "optimize/point_trace.hpp"
#include "optimize/search_types.hpp"

namespace fird::distributed {

// A rank that did not answer in time, one whose share failed (its error), or a run
// stopped (mpirun's SIGTERM when a rank died) while rank 0 waited on ranks: the one line
// names them.
struct RankLost : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct FarmStats {
    std::uint64_t batches = 0;
    std::uint64_t points_here = 0, points_elsewhere = 0;
    std::uint64_t bytes_out = 0, bytes_in = 0; // batches and results
    std::uint64_t bytes_desired = 0;           // the desired far field, once to each rank
    double here_ms = 0.0;                      // rank 0 tracing its own shares
    double wait_ms = 0.0;                      // rank 0 waiting on the others' shares
    // Rank 0's own work between one batch's end and the next one's start (the search's
    // bookkeeping: the serial part that bounds how far more ranks help), and the points of
    // the batches that followed such a gap.
    double between_ms = 0.0;
    std::uint64_t points_after_gaps = 0;
};

// Rank 0's side. `control` (may be null) is the search's: a stop asked while waiting on
// ranks ends the wait, and its stop_note names the ranks waited on while a batch is out.
// `rank_timeout_s`: the longest wait on a rank for a batch's share; unset: 60 s plus ten
// times what rank 0 took for its own share of that batch. `after_loss` ends each RankLost
// line (where the search's record is kept, how to continue it).
class Farm {
  public:
    Farm(const Job& job, Backend backend, SearchControl* control,
         std::optional<double> rank_timeout_s, std::string after_loss);
    // Tells the other ranks the run is over (not after a lost rank: the job is aborted).
    ~Farm();
    Farm(const Farm&) = delete;
    Farm& operator=(const Farm&) = delete;

    // The hook for SearchSettings::distributed.
    DistributedTrace tracing();
    std::vector<CandidateResult> trace(const StageBatch& batch);
    const FarmStats& stats() const { return stats_; }
    // One line: ranks, points traced elsewhere, bytes per point, rank 0's waiting share of
    // `elapsed_s`.
    std::string summary(double elapsed_s) const;

  private:
    const Job* job_;
    Backend backend_;
    SearchControl* control_;
    std::optional<double> rank_timeout_s_;
    std::string after_loss_;
    std::string note_; // control_->stop_note while a batch is out
    std::vector<bool> desired_sent_;
    // Messages in flight stay alive here until the run ends.
    std::vector<std::vector<unsigned char>> sent_;
    FarmStats stats_;
    std::optional<std::chrono::steady_clock::time_point> last_batch_end_;
    bool lost_ = false;
};

// A rank other than 0: traces the shares rank 0 sends until it says the run is over.
// Returns the process's exit code. A share that fails is answered with its error (rank 0
// ends the run with it).
int serve_batches(const Job& job, PointTracer& tracer);

} // namespace fird::distributed
