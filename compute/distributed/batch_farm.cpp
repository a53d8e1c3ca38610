#include "batch_farm.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>
#include <type_traits>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <mpi.h>

namespace fird::distributed {

namespace {

enum Tag : int { kBatch = 1, kDesired = 2, kDone = 3, kResults = 4, kError = 5 };

// Fixed-size values and arrays of doubles, in this machine's byte order: every rank of a
// job runs the same build, on the same kind of node.
struct Writer {
    std::vector<unsigned char> bytes;
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const unsigned char*>(&v);
        bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    void put(std::span<const double> values) {
        const auto* p = reinterpret_cast<const unsigned char*>(values.data());
        bytes.insert(bytes.end(), p, p + values.size_bytes());
    }
};

struct Reader {
    const std::vector<unsigned char>& bytes;
    std::size_t at = 0;
    void take(void* out, std::size_t n) {
        if (at + n > bytes.size()) throw std::runtime_error("a message from rank 0 is cut short");
        std::memcpy(out, bytes.data() + at, n);
        at += n;
    }
    template <class T> T get() {
        T v;
        take(&v, sizeof(T));
        return v;
    }
    void get(std::span<double> out) { take(out.data(), out.size_bytes()); }
};

// A message that has arrived from `source` (any tag), read whole.
std::vector<unsigned char> receive(int source, const MPI_Status& probed) {
    int count = 0;
    MPI_Get_count(&probed, MPI_BYTE, &count);
    std::vector<unsigned char> bytes(std::size_t(std::max(count, 0)));
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
// has traced this many points.
std::optional<std::uint64_t> test_hook(const char* name, const Job& job) {
    const char* v = std::getenv(name);
    if (!v || job.rank() != job.size() - 1) return std::nullopt;
    return std::strtoull(v, nullptr, 10);
}

} // namespace

// Why rank 0 stopped waiting when asked to stop: under mpirun most often because a rank
// died (mpirun then sends SIGTERM to the others, and SIGKILL a moment later).
static std::string stopped_waiting(const std::vector<int>& pending) {
    return fmt::format("the run was stopped (Ctrl-C, or mpirun's SIGTERM after one of its ranks "
                       "ended) while rank 0 waited on rank {}",
                       fmt::join(pending, ", "));
}

Farm::Farm(const Job& job, Backend backend, SearchControl* control,
           std::optional<double> rank_timeout_s, std::string after_loss)
    : job_(&job), backend_(backend), control_(control), rank_timeout_s_(rank_timeout_s),
      after_loss_(std::move(after_loss)), desired_sent_(std::size_t(job.size()), false) {}

Farm::~Farm() {
    if (lost_) return;
    for (int r = 1; r < job_->size(); ++r)
        MPI_Send(nullptr, 0, MPI_BYTE, r, kDone, MPI_COMM_WORLD);
}

DistributedTrace Farm::tracing() {
    return {.processes = std::size_t(job_->size()),
            .trace = [this](const StageBatch& b) { return trace(b); }};
}

std::vector<CandidateResult> Farm::trace(const StageBatch& b) {
    const std::size_t n = b.points.size(), ranks = std::size_t(job_->size());
    if (last_batch_end_) {
        stats_.between_ms += ms_since(*last_batch_end_);
        stats_.points_after_gaps += n;
    }
    // Contiguous shares whose sizes differ by one at most; rank 0 keeps the first.
    std::vector<std::size_t> first(ranks + 1);
    for (std::size_t r = 0; r <= ranks; ++r)
        first[r] = n * r / ranks;
    std::vector<MPI_Request> requests;
    const auto send = [&](int rank, Tag tag, std::vector<unsigned char> bytes) {
        sent_.push_back(std::move(bytes));
        requests.emplace_back();
        MPI_Isend(sent_.back().data(), int(sent_.back().size()), MPI_BYTE, rank, tag,
                  MPI_COMM_WORLD, &requests.back());
        return sent_.back().size();
    };
    std::vector<int> pending;
    for (std::size_t r = 1; r < ranks; ++r) {
        if (first[r] == first[r + 1]) continue;
        if (!desired_sent_[r]) {
            Writer w;
            w.put(b.desired.width);
            w.put(b.desired.height);
            w.put(std::span<const double>(b.desired.lm));
            stats_.bytes_desired += send(int(r), kDesired, std::move(w.bytes));
            desired_sent_[r] = true;
        }
        Writer w;
        const Fidelity& f = b.fidelity;
        for (std::uint64_t v :
             {std::uint64_t(backend_), f.rays, f.seed, std::uint64_t(f.farfield_w),
              std::uint64_t(f.farfield_h), std::uint64_t(f.heightfield_w),
              std::uint64_t(f.heightfield_h), std::uint64_t(first[r + 1] - first[r]),
              std::uint64_t(b.points[first[r]].size())})
            w.put(v);
        for (std::size_t k = first[r]; k < first[r + 1]; ++k)
            w.put(std::span<const double>(b.points[k]));
        stats_.bytes_out += send(int(r), kBatch, std::move(w.bytes));
        stats_.points_elsewhere += first[r + 1] - first[r];
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
    // Fewer points than ranks leave rank 0 none (the shares are ranks' last-first).
    std::vector<CandidateResult> here;
    if (first[1] > 0) here = b.trace_here(b.points.subspan(0, first[1]));
    const double here_ms = ms_since(t_here);
    stats_.here_ms += here_ms;
    stats_.points_here += first[1];
    ++stats_.batches;
    std::vector<CandidateResult> results(n);
    std::move(here.begin(), here.end(), results.begin());

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
            const std::vector<unsigned char> bytes = receive(*it, status);
            if (status.MPI_TAG == kError) {
                lost_ = true;
                throw RankLost(std::string(bytes.begin(), bytes.end()) + after_loss_);
            }
            const std::size_t r = std::size_t(*it);
            if (bytes.size() != (first[r + 1] - first[r]) * 3 * sizeof(double))
                throw std::runtime_error(
                    fmt::format("rank {} answered a batch with {} bytes", r, bytes.size()));
            stats_.bytes_in += bytes.size();
            Reader in{bytes};
            for (std::size_t k = first[r]; k < first[r + 1]; ++k) {
                results[k].l2_lm = in.get<double>();
                results[k].farfield_lm = in.get<double>();
                results[k].wall_ms = in.get<double>();
            }
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
    return results;
}

std::string Farm::summary(double elapsed_s) const {
    const FarmStats& s = stats_;
    const double per_point =
        s.points_elsewhere ? double(s.bytes_out + s.bytes_in) / double(s.points_elsewhere) : 0.0;
    const int others = job_->size() - 1;
    return fmt::format(
        "{} ranks: {} batches, {} candidates traced on {} and {} on rank 0; {:.0f} bytes "
        "exchanged per candidate traced elsewhere (and the desired far field, {} bytes in all, "
        "once to each rank); rank 0 traced {:.2f} s, waited {:.2f} s of {:.2f} s ({:.1f}%) and "
        "spent {:.3f} ms per candidate between batches",
        job_->size(), s.batches, s.points_elsewhere,
        others == 1 ? std::string("rank 1") : fmt::format("ranks 1-{}", others), s.points_here,
        per_point, s.bytes_desired, s.here_ms * 1e-3, s.wait_ms * 1e-3, elapsed_s,
        elapsed_s > 0.0 ? 100.0 * s.wait_ms * 1e-3 / elapsed_s : 0.0,
        s.points_after_gaps ? s.between_ms / double(s.points_after_gaps) : 0.0);
}

int serve_batches(const Job& job, PointTracer& tracer) {
    const std::optional<std::uint64_t> exit_after = test_hook("FIRD_TEST_RANK_EXIT_AFTER", job),
                                       hang_after = test_hook("FIRD_TEST_RANK_HANG_AFTER", job);
    FarField desired;
    std::uint64_t traced = 0;
    for (;;) {
        int arrived = 0;
        MPI_Status status;
        while (!arrived) {
            MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
            if (!arrived) std::this_thread::sleep_for(kPoll);
        }
        const std::vector<unsigned char> bytes = receive(0, status);
        if (status.MPI_TAG == kDone) return 0;
        std::string error;
        try {
            Reader in{bytes};
            if (status.MPI_TAG == kDesired) {
                desired.width = in.get<std::uint32_t>();
                desired.height = in.get<std::uint32_t>();
                desired.lm.resize(std::size_t(desired.width) * desired.height);
                in.get(desired.lm);
                continue;
            }
            if (exit_after && traced >= *exit_after) std::_Exit(3);
            while (hang_after && traced >= *hang_after)
                std::this_thread::sleep_for(std::chrono::seconds(1));
            const Backend backend = Backend(in.get<std::uint64_t>());
            Fidelity f;
            f.rays = in.get<std::uint64_t>();
            f.seed = in.get<std::uint64_t>();
            f.farfield_w = std::uint32_t(in.get<std::uint64_t>());
            f.farfield_h = std::uint32_t(in.get<std::uint64_t>());
            f.heightfield_w = std::uint32_t(in.get<std::uint64_t>());
            f.heightfield_h = std::uint32_t(in.get<std::uint64_t>());
            const std::size_t n = in.get<std::uint64_t>(), dim = in.get<std::uint64_t>();
            std::vector<std::vector<double>> points(n, std::vector<double>(dim));
            for (std::vector<double>& x : points)
                in.get(x);
            const std::vector<CandidateResult> results = tracer.trace(f, backend, desired, points);
            Writer out;
            for (const CandidateResult& r : results) {
                out.put(r.l2_lm.value_or(0.0));
                out.put(r.farfield_lm);
                out.put(r.wall_ms);
            }
            MPI_Send(out.bytes.data(), int(out.bytes.size()), MPI_BYTE, 0, kResults,
                     MPI_COMM_WORLD);
            traced += n;
        } catch (const std::exception& e) {
            error = fmt::format("rank {}: {}", job.rank(), e.what());
        }
        if (!error.empty())
            MPI_Send(error.data(), int(error.size()), MPI_BYTE, 0, kError, MPI_COMM_WORLD);
    }
}

} // namespace fird::distributed
