// Lists of independent work shared among the ranks of an MPI job: rank 0 splits a list into
// contiguous shares, sends each other rank its share's request, works the first share itself
// and reads the others' answers; the other ranks answer requests until rank 0 says the run is
// over. What a request and an answer hold is the command's (search_shares.hpp,
// tolerance_shares.hpp): parameters out, numbers back. Before a rank's first share it gets the
// run's setup once (the desired far field).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "distributed/job.hpp"
#include "distributed/message.hpp"
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
    std::uint64_t items_here = 0, items_elsewhere = 0;
    std::uint64_t bytes_out = 0, bytes_in = 0; // requests and answers
    std::uint64_t bytes_setup = 0;             // the setup, once to each rank
    double here_ms = 0.0;                      // rank 0 working its own shares
    double wait_ms = 0.0;                      // rank 0 waiting on the others' shares
    // Rank 0's own work between one batch's end and the next one's start (the search's
    // bookkeeping: the serial part that bounds how far more ranks help), and the items of
    // the batches that followed such a gap.
    double between_ms = 0.0;
    std::uint64_t items_after_gaps = 0;
};

// One list shared out: `request` writes the message for items [first, last), `here` works
// rank 0's share, `answer` reads a rank's reply for its share.
struct ShareOut {
    std::size_t items = 0;
    std::function<Bytes(std::size_t first, std::size_t last)> request;
    std::function<void(std::size_t first, std::size_t last)> here;
    std::function<void(std::size_t first, std::size_t last, Reader& reply)> answer;
};

// Rank 0's side. `control` (may be null): a stop asked while waiting on ranks ends the wait,
// and its stop_note names the ranks waited on while a batch is out. `rank_timeout_s`: the
// longest wait on a rank for a share; unset: 60 s plus ten times what rank 0 took for its
// own share of that batch. `after_loss` ends each RankLost line (where the record is kept,
// how to continue).
class Farm {
  public:
    Farm(const Job& job, SearchControl* control, std::optional<double> rank_timeout_s,
         std::string after_loss);
    // Tells the other ranks the run is over (not after a lost rank: the job is aborted).
    ~Farm();
    Farm(const Farm&) = delete;
    Farm& operator=(const Farm&) = delete;

    int ranks() const { return job_->size(); }
    // The run's desired far field (null: none), sent to each rank before its first share
    // and not again; the first one given stays.
    void set_setup_once(const FarField* desired) {
        if (setup_) return;
        Writer w;
        w.put(desired);
        setup_ = std::move(w.bytes);
    }
    void share(const ShareOut& work);
    const FarmStats& stats() const { return stats_; }
    // One line: ranks, items worked elsewhere, bytes per item, rank 0's waiting share of
    // `elapsed_s`; `items` names them ("candidates").
    std::string summary(double elapsed_s, const std::string& items) const;

  private:
    const Job* job_;
    SearchControl* control_;
    std::optional<double> rank_timeout_s_;
    std::string after_loss_;
    std::optional<Bytes> setup_;
    std::vector<bool> setup_sent_;
    std::vector<Bytes> sent_; // messages in flight stay alive here until answered
    std::string note_;        // control_->stop_note while a batch is out
    FarmStats stats_;
    std::optional<std::chrono::steady_clock::time_point> last_batch_end_;
    bool lost_ = false;
};

// A rank other than 0: what it does with the run's setup and with each share's request.
struct ShareWorker {
    std::function<void(const Bytes& setup)> setup;
    std::function<Bytes(const Bytes& request)> work;
};

// Answers rank 0's requests until it says the run is over; returns the exit code. A share
// that fails is answered with its error (rank 0 ends the run with it).
int serve_shares(const Job& job, const ShareWorker& worker);

} // namespace fird::distributed
