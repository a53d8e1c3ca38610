#include "batch_farm.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <thread>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <mpi.h>

namespace fird::distributed {

namespace {

enum Tag : int { kRequest = 1, kSetup = 2, kDone = 3, kAnswer = 4, kError = 5 };

// A message that has arrived from `source` (any tag), read whole.
Bytes receive(int source, const MPI_Status& probed) {
    int count = 0;
    MPI_Get_count(&probed, MPI_BYTE, &count);
    Bytes bytes(std::size_t(std::max(count, 0)));
    MPI_Recv(bytes.data(), count, MPI_BYTE, source, probed.MPI_TAG, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    return bytes;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Waiting ranks poll with a short sleep: MPI's blocking calls spin, which would take a core
// from the ranks tracing beside them on the same node.
constexpr auto kPoll = std::chrono::microseconds(250);

// The test hooks of the fault tests: the job's last rank ends (exit 3) or hangs once it
// has answered this many shares.
std::optional<std::uint64_t> test_hook(const char* name, const Job& job) {
    const char* v = std::getenv(name);
    if (!v || job.rank() != job.size() - 1) return std::nullopt;
    return std::strtoull(v, nullptr, 10);
}

// Why rank 0 stopped waiting when asked to stop: under mpirun most often because a rank
// died (mpirun then sends SIGTERM to the others, and SIGKILL a moment later).
std::string stopped_waiting(const std::vector<int>& pending) {
    return fmt::format("the run was stopped (Ctrl-C, or mpirun's SIGTERM after one of its ranks "
                       "ended) while rank 0 waited on rank {}",
                       fmt::join(pending, ", "));
}

} // namespace

Farm::Farm(const Job& job, SearchControl* control, std::optional<double> rank_timeout_s,
           std::string after_loss)
    : job_(&job), control_(control), rank_timeout_s_(rank_timeout_s),
      after_loss_(std::move(after_loss)), setup_sent_(std::size_t(job.size()), false) {}

Farm::~Farm() {
    if (lost_) return;
    for (int r = 1; r < job_->size(); ++r)
        MPI_Send(nullptr, 0, MPI_BYTE, r, kDone, MPI_COMM_WORLD);
}

void Farm::share(const ShareOut& work) {
    const std::size_t n = work.items, ranks = std::size_t(job_->size());
    if (last_batch_end_) {
        stats_.between_ms += ms_since(*last_batch_end_);
        stats_.items_after_gaps += n;
    }
    // Contiguous shares whose sizes differ by one at most; rank 0 keeps the first.
    std::vector<std::size_t> first(ranks + 1);
    for (std::size_t r = 0; r <= ranks; ++r)
        first[r] = n * r / ranks;
    std::vector<MPI_Request> requests;
    const auto send = [&](int rank, Tag tag, const Bytes& bytes) {
        sent_.push_back(bytes);
        requests.emplace_back();
        MPI_Isend(sent_.back().data(), int(sent_.back().size()), MPI_BYTE, rank, tag,
                  MPI_COMM_WORLD, &requests.back());
        return sent_.back().size();
    };
    sent_.reserve(2 * ranks); // no reallocation while a message is in flight
    std::vector<int> pending;
    for (std::size_t r = 1; r < ranks; ++r) {
        if (first[r] == first[r + 1]) continue;
        if (setup_ && !setup_sent_[r]) {
            stats_.bytes_setup += send(int(r), kSetup, *setup_);
            setup_sent_[r] = true;
        }
        stats_.bytes_out += send(int(r), kRequest, work.request(first[r], first[r + 1]));
        stats_.items_elsewhere += first[r + 1] - first[r];
        pending.push_back(int(r));
    }

    // Said at once by the signal handler should mpirun stop this process (it kills it
    // moments later); cleared however this batch ends.
    note_ = fmt::format("fird: error: {}{}\n", stopped_waiting(pending), after_loss_);
    struct NoteScope {
        SearchControl* control;
        ~NoteScope() {
            if (control) control->stop_note.store(nullptr);
        }
    } note_scope{control_};
    if (control_ && !pending.empty()) control_->stop_note.store(note_.c_str());

    const auto t_here = std::chrono::steady_clock::now();
    // Fewer items than ranks leave rank 0 none (the shares are the ranks' last-first).
    if (first[1] > 0) work.here(0, first[1]);
    const double here_ms = ms_since(t_here);
    stats_.here_ms += here_ms;
    stats_.items_here += first[1];
    ++stats_.batches;

    const double timeout_s = rank_timeout_s_ ? *rank_timeout_s_ : 60.0 + 10.0 * here_ms * 1e-3;
    const auto t_wait = std::chrono::steady_clock::now();
    while (!pending.empty()) {
        for (auto it = pending.begin(); it != pending.end();) {
            int arrived = 0;
            MPI_Status status;
            MPI_Iprobe(*it, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
            if (!arrived) {
                ++it;
                continue;
            }
            const Bytes bytes = receive(*it, status);
            if (status.MPI_TAG == kError) {
                lost_ = true;
                throw RankLost(std::string(bytes.begin(), bytes.end()) + after_loss_);
            }
            const std::size_t r = std::size_t(*it);
            stats_.bytes_in += bytes.size();
            Reader reply{bytes};
            work.answer(first[r], first[r + 1], reply);
            it = pending.erase(it);
        }
        if (pending.empty()) break;
        if (control_ && control_->stop.load()) {
            lost_ = true;
            throw RankLost(stopped_waiting(pending) + after_loss_);
        }
        if (ms_since(t_wait) > timeout_s * 1e3) {
            lost_ = true;
            throw RankLost(fmt::format("rank {} did not answer within {:.0f} s (--rank-timeout)",
                                       pending.front(), timeout_s) +
                           after_loss_);
        }
        std::this_thread::sleep_for(kPoll);
    }
    // Every rank answered, so every message to it was received.
    MPI_Waitall(int(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
    sent_.clear();
    stats_.wait_ms += ms_since(t_wait);
    last_batch_end_ = std::chrono::steady_clock::now();
}

std::string Farm::summary(double elapsed_s, const std::string& items) const {
    const FarmStats& s = stats_;
    const double per_item =
        s.items_elsewhere ? double(s.bytes_out + s.bytes_in) / double(s.items_elsewhere) : 0.0;
    const int others = job_->size() - 1;
    return fmt::format(
        "{} ranks: {} batches, {} {} traced on {} and {} on rank 0; {:.0f} bytes exchanged for "
        "each traced elsewhere{}; rank 0 traced {:.2f} s, waited {:.2f} s of {:.2f} s ({:.1f}%) "
        "and spent {:.3f} ms on each between batches",
        job_->size(), s.batches, s.items_elsewhere, items,
        others == 1 ? std::string("rank 1") : fmt::format("ranks 1-{}", others), s.items_here,
        per_item,
        s.bytes_setup ? fmt::format(" (and the desired far field, {} bytes in all, once to each "
                                    "rank)",
                                    s.bytes_setup)
                      : std::string(),
        s.here_ms * 1e-3, s.wait_ms * 1e-3, elapsed_s,
        elapsed_s > 0.0 ? 100.0 * s.wait_ms * 1e-3 / elapsed_s : 0.0,
        s.items_after_gaps ? s.between_ms / double(s.items_after_gaps) : 0.0);
}

int serve_shares(const Job& job, const ShareWorker& worker) {
    const std::optional<std::uint64_t> exit_after = test_hook("FIRD_TEST_RANK_EXIT_AFTER", job),
                                       hang_after = test_hook("FIRD_TEST_RANK_HANG_AFTER", job);
    std::uint64_t shares = 0;
    for (;;) {
        int arrived = 0;
        MPI_Status status;
        while (!arrived) {
            MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
            if (!arrived) std::this_thread::sleep_for(kPoll);
        }
        const Bytes bytes = receive(0, status);
        if (status.MPI_TAG == kDone) return 0;
        std::string error;
        try {
            if (status.MPI_TAG == kSetup) {
                worker.setup(bytes);
                continue;
            }
            if (exit_after && shares >= *exit_after) std::_Exit(3);
            while (hang_after && shares >= *hang_after)
                std::this_thread::sleep_for(std::chrono::seconds(1));
            const Bytes answer = worker.work(bytes);
            MPI_Send(answer.data(), int(answer.size()), MPI_BYTE, 0, kAnswer, MPI_COMM_WORLD);
            ++shares;
        } catch (const std::exception& e) {
            error = fmt::format("rank {}: {}", job.rank(), e.what());
        }
        if (!error.empty())
            MPI_Send(error.data(), int(error.size()), MPI_BYTE, 0, kError, MPI_COMM_WORLD);
    }
}

} // namespace fird::distributed
