// `fird bench`: run time against error for the fast path, over height-field sizes, ray
// counts, hit modes and scenes, with l2 to a CPU reference and the noise expected.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "model/scene.hpp"
#include "vk/context.hpp"

namespace fird {

struct BenchOptions {
    std::vector<std::string> scenes;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> heightfields{
        {300, 200}, {600, 400}, {1200, 800}, {2400, 1600}};
    std::vector<std::uint64_t> rays{100000, 1000000, 10000000};
    std::vector<HitMode> modes{HitMode::Paper, HitMode::Refined};
    std::uint64_t reference_rays = 2000000;
    // Also trace the reference with each row's own rays (CPU time grows with the rays).
    bool same_rays = false;
    // Only rows [first_row, last_row) of the sweep, in its order (scenes, height fields,
    // ray counts, modes): a rank's share of it (distributed/bench_shares.hpp).
    std::size_t first_row = 0, last_row = SIZE_MAX;
};

// The sweep's rows: scenes x height fields x ray counts x modes.
std::size_t bench_row_count(const BenchOptions& options);

struct BenchRow {
    std::string scene;
    std::uint32_t hf_w = 0, hf_h = 0;
    std::uint64_t rays = 0, effective = 0, aborted = 0;
    std::string mode;
    double rayset_ms = 0, heightfield_ms = 0, trace_ms = 0, histogram_ms = 0, compare_ms = 0;
    double rays_per_s = 0; // effective rays per second of trace stage
    double l2_lm = 0;      // to the reference far field
    // The l2 expected from Monte Carlo noise alone with the row's sampler: the multinomial
    // formula for independent rays ("multinomial"), measured from a replicate trace for any
    // other ("replicate"); the reference's own noise (independent rays) added.
    double noise_lm = 0;
    std::string noise_from;
    double l2_same_rays_lm = -1; // to the reference of the same rays (-1: not traced)
    int rank = 0;                // the rank of an MPI job that measured it (0: one process)
};

// Runs every combination; `progress` (may be empty) is called after each row.
std::vector<BenchRow> run_bench(const vk::Context& ctx, const BenchOptions& options,
                                const std::function<void(const BenchRow&)>& progress);

std::string bench_markdown(const std::vector<BenchRow>& rows, const std::string& device);
void write_bench_csv(const std::string& path, const std::vector<BenchRow>& rows);
// Trace time against l2 / noise, log-log, one colour per hit mode.
void write_bench_plot(const std::string& path, const std::vector<BenchRow>& rows);

} // namespace fird

namespace fird {

// fird bench --skips: for each scene and each piece of work the fast path skips when the
// scene does not need it, the time of an evaluation with the skip and without it (the
// switch turned off for the measurement only), median of `reps` alternating runs.
struct SkipRow {
    std::string scene;
    std::string skip;
    double with_ms = 0.0, without_ms = 0.0;
    std::string note;
    int rank = 0; // the rank of an MPI job that measured it
};
std::vector<SkipRow> run_skips_bench(const vk::Context& ctx, const std::vector<std::string>& scenes,
                                     int reps, const std::function<void(const SkipRow&)>& progress);
std::string skips_markdown(const std::vector<SkipRow>& rows, const std::string& device);

// The device a bench ran on, as its tables name it: "name (driver)".
std::string bench_device(const vk::Context& ctx);

// The median of a set of timings (the upper middle one for an even count; 0 when empty).
double median_ms(std::vector<double> timings);

// One candidate of a search as the optimizer pays for it (fird bench --candidates): the
// rayset kept, the height field rebuilt (two reflectors alternate), the trace, histogram
// and, with a [target], the compare; medians over `reps` after one warm evaluation.
struct CandidateRow {
    std::string scene;
    std::uint64_t rays = 0;
    int reps = 0;
    double candidate_ms = 0.0; // wall time of Evaluator::evaluate
    double heightfield_ms = 0.0, trace_ms = 0.0, histogram_ms = 0.0, compare_ms = 0.0;
    std::uint64_t submissions = 0; // host waits per candidate (median)
    // The same candidates K at a time (Evaluator::evaluate_batch, each height field rebuilt):
    // the batch's wall time over K, and its submissions (medians). K 1: not measured.
    std::uint64_t batch = 1;
    double batch_candidate_ms = 0.0;
    std::uint64_t batch_submissions = 0;
    int rank = 0; // the rank of an MPI job that measured it
};
// rays 0: each scene's own; batch: K of the batched measurement (1: none).
std::vector<CandidateRow> run_candidate_bench(const vk::Context& ctx,
                                              const std::vector<std::string>& scenes,
                                              std::uint64_t rays, int reps, std::uint64_t batch);
std::string candidates_markdown(const std::vector<CandidateRow>& rows, const std::string& device);
// candidates.csv: scene, rays, reps, candidate_ms, heightfield_ms, trace_ms, histogram_ms,
// compare_ms, submissions, batch, batch_candidate_ms, batch_submissions, rank (written whole or
// not at all).
void write_candidates_csv(const std::string& path, const std::vector<CandidateRow>& rows);

} // namespace fird
