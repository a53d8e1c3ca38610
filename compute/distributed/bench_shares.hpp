// fird bench across ranks: the sweep's rows (a plain bench), or its scenes (--candidates,
// --skips), as the farm's shares, each measured on the device of the rank that takes it.
// A request holds the share's first and last index (every rank parsed the same command
// line, so it knows the sweep); an answer the rank, its device and the measured rows.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "bench/bench.hpp"
#include "distributed/batch_farm.hpp"

namespace fird::distributed {

// What the ranks measured, in the sweep's order, and each rank's device ("name (driver)").
template <class Row> struct SharedBench {
    std::vector<Row> rows;
    std::map<int, std::string> devices;
};

enum class BenchKind { Sweep, Candidates, Skips };

// What one bench measures, as every rank sets it from the command line.
struct BenchWork {
    BenchKind kind = BenchKind::Sweep;
    BenchOptions sweep;                // Sweep
    std::vector<std::string> scenes;   // Candidates, Skips
    std::uint64_t rays = 0, batch = 1; // Candidates
    int reps = 1;                      // Candidates, Skips
};

// Rank 0's side: the rows shared out, rank 0 measuring the first share on `ctx`.
SharedBench<BenchRow> shared_sweep(Farm& farm, const vk::Context& ctx, const BenchWork& work);
SharedBench<CandidateRow> shared_candidates(Farm& farm, const vk::Context& ctx,
                                            const BenchWork& work);
SharedBench<SkipRow> shared_skips(Farm& farm, const vk::Context& ctx, const BenchWork& work);

// A rank's side: its shares measured on its device.
ShareWorker bench_worker(const vk::Context& ctx, int rank, const BenchWork& work);

// The markdown tables' device line: one device, or each rank's.
std::string devices_line(const std::map<int, std::string>& devices);

} // namespace fird::distributed
