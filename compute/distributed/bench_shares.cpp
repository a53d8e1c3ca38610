#include "bench_shares.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace fird::distributed {

namespace {

std::string device_of(const vk::Context& ctx) {
    return ctx.summary().name + " (" + ctx.summary().driver_info + ")";
}

// Each row kind's numbers and names, written and read in one order.
void put_row(Writer& w, const BenchRow& r) {
    w.put(r.scene);
    w.put(r.hf_w);
    w.put(r.hf_h);
    w.put(r.rays);
    w.put(r.effective);
    w.put(r.aborted);
    w.put(r.mode);
    for (const double v : {r.rayset_ms, r.heightfield_ms, r.trace_ms, r.histogram_ms, r.compare_ms,
                           r.rays_per_s, r.l2_lm, r.noise_lm, r.l2_same_rays_lm})
        w.put(v);
    w.put(r.noise_from);
}
void get_row(Reader& in, BenchRow& r) {
    r.scene = in.text();
    r.hf_w = in.get<std::uint32_t>();
    r.hf_h = in.get<std::uint32_t>();
    r.rays = in.get<std::uint64_t>();
    r.effective = in.get<std::uint64_t>();
    r.aborted = in.get<std::uint64_t>();
    r.mode = in.text();
    for (double* v : {&r.rayset_ms, &r.heightfield_ms, &r.trace_ms, &r.histogram_ms, &r.compare_ms,
                      &r.rays_per_s, &r.l2_lm, &r.noise_lm, &r.l2_same_rays_lm})
        *v = in.get<double>();
    r.noise_from = in.text();
}

void put_row(Writer& w, const CandidateRow& r) {
    w.put(r.scene);
    w.put(r.rays);
    w.put(r.reps);
    for (const double v : {r.candidate_ms, r.heightfield_ms, r.trace_ms, r.histogram_ms,
                           r.compare_ms, r.batch_candidate_ms})
        w.put(v);
    w.put(r.submissions);
    w.put(r.batch);
    w.put(r.batch_submissions);
}
void get_row(Reader& in, CandidateRow& r) {
    r.scene = in.text();
    r.rays = in.get<std::uint64_t>();
    r.reps = in.get<int>();
    for (double* v : {&r.candidate_ms, &r.heightfield_ms, &r.trace_ms, &r.histogram_ms,
                      &r.compare_ms, &r.batch_candidate_ms})
        *v = in.get<double>();
    r.submissions = in.get<std::uint64_t>();
    r.batch = in.get<std::uint64_t>();
    r.batch_submissions = in.get<std::uint64_t>();
}

void put_row(Writer& w, const SkipRow& r) {
    w.put(r.scene);
    w.put(r.skip);
    w.put(r.with_ms);
    w.put(r.without_ms);
    w.put(r.note);
}
void get_row(Reader& in, SkipRow& r) {
    r.scene = in.text();
    r.skip = in.text();
    r.with_ms = in.get<double>();
    r.without_ms = in.get<double>();
    r.note = in.text();
}

// Items [first, last) of the work measured here: sweep rows, or scenes.
std::vector<BenchRow> measure_sweep(const vk::Context& ctx, const BenchWork& work,
                                    std::size_t first, std::size_t last) {
    BenchOptions o = work.sweep;
    o.first_row = first;
    o.last_row = last;
    return run_bench(ctx, o, {});
}
std::vector<std::string> scenes_of(const BenchWork& work, std::size_t first, std::size_t last) {
    return {work.scenes.begin() + std::ptrdiff_t(first),
            work.scenes.begin() + std::ptrdiff_t(last)};
}
std::vector<CandidateRow> measure_candidates(const vk::Context& ctx, const BenchWork& work,
                                             std::size_t first, std::size_t last) {
    return run_candidate_bench(ctx, scenes_of(work, first, last), work.rays, work.reps, work.batch);
}
std::vector<SkipRow> measure_skips(const vk::Context& ctx, const BenchWork& work, std::size_t first,
                                   std::size_t last) {
    return run_skips_bench(ctx, scenes_of(work, first, last), work.reps, {});
}

// The answer: the rank, its device, then its rows (a count, then each).
template <class Row> Bytes answer(const vk::Context& ctx, int rank, const std::vector<Row>& rows) {
    Writer w;
    w.put(rank);
    w.put(device_of(ctx));
    w.put(std::uint64_t(rows.size()));
    for (const Row& r : rows)
        put_row(w, r);
    return w.bytes;
}

// Shares items out: rank 0 measures the first share with `measure`, the others theirs; the
// rows come back in the items' order (a share's rows in its items' order).
template <class Row, class Measure>
SharedBench<Row> shared(Farm& farm, const vk::Context& ctx, std::size_t items,
                        const Measure& measure) {
    std::vector<std::vector<Row>> by_share(items); // each share's rows at its first item
    SharedBench<Row> out;
    out.devices[0] = device_of(ctx);
    farm.share({.items = items,
                .request =
                    [](std::size_t first, std::size_t last) {
                        Writer w;
                        w.put(std::uint64_t(first));
                        w.put(std::uint64_t(last));
                        return w.bytes;
                    },
                .here = [&](std::size_t first,
                            std::size_t last) { by_share[first] = measure(first, last); },
                .answer =
                    [&](std::size_t first, std::size_t, Reader& in) {
                        const int rank = in.get<int>();
                        out.devices[rank] = in.text();
                        std::vector<Row> rows(in.get<std::uint64_t>());
                        for (Row& r : rows) {
                            get_row(in, r);
                            r.rank = rank;
                        }
                        by_share[first] = std::move(rows);
                    }});
    for (std::vector<Row>& rows : by_share)
        for (Row& r : rows)
            out.rows.push_back(std::move(r));
    return out;
}

} // namespace

SharedBench<BenchRow> shared_sweep(Farm& farm, const vk::Context& ctx, const BenchWork& work) {
    return shared<BenchRow>(
        farm, ctx, bench_row_count(work.sweep),
        [&](std::size_t first, std::size_t last) { return measure_sweep(ctx, work, first, last); });
}

SharedBench<CandidateRow> shared_candidates(Farm& farm, const vk::Context& ctx,
                                            const BenchWork& work) {
    return shared<CandidateRow>(farm, ctx, work.scenes.size(),
                                [&](std::size_t first, std::size_t last) {
                                    return measure_candidates(ctx, work, first, last);
                                });
}

SharedBench<SkipRow> shared_skips(Farm& farm, const vk::Context& ctx, const BenchWork& work) {
    return shared<SkipRow>(farm, ctx, work.scenes.size(), [&](std::size_t first, std::size_t last) {
        return measure_skips(ctx, work, first, last);
    });
}

ShareWorker bench_worker(const vk::Context& ctx, int rank, const BenchWork& work) {
    return {.setup = [](const Bytes&) {},
            .work =
                [&ctx, rank, &work](const Bytes& bytes) {
                    Reader in{bytes};
                    const auto first = std::size_t(in.get<std::uint64_t>());
                    const auto last = std::size_t(in.get<std::uint64_t>());
                    switch (work.kind) {
                    case BenchKind::Sweep:
                        return answer(ctx, rank, measure_sweep(ctx, work, first, last));
                    case BenchKind::Candidates:
                        return answer(ctx, rank, measure_candidates(ctx, work, first, last));
                    case BenchKind::Skips:
                        break;
                    }
                    return answer(ctx, rank, measure_skips(ctx, work, first, last));
                }};
}

std::string devices_line(const std::map<int, std::string>& devices) {
    const bool one_kind = std::all_of(devices.begin(), devices.end(), [&](const auto& d) {
        return d.second == devices.begin()->second;
    });
    if (one_kind && !devices.empty())
        return fmt::format("{}, on each of {} ranks", devices.begin()->second, devices.size());
    std::string line;
    for (const auto& [rank, device] : devices)
        line += fmt::format("{}rank {}: {}", line.empty() ? "" : "; ", rank, device);
    return line;
}

} // namespace fird::distributed
