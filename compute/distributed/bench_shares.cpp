#include "bench_shares.hpp"

#include <algorithm>
#include <string>
#include <type_traits>

#include <fmt/format.h>

namespace fird::distributed {

namespace {

// A message's field both ways: written from a row (Out) or read into one (In), so that each
// row kind's fields are listed once, in one order (fields() below).
struct Out {
    Writer& w;
    template <class T> void operator()(const T& v) { w.put(v); }
};
struct In {
    Reader& r;
    template <class T> void operator()(T& v) {
        if constexpr (std::is_same_v<T, std::string>)
            v = r.text();
        else
            v = r.template get<T>();
    }
};

template <class Field, class Row> void fields(Field&& f, Row& r) {
    if constexpr (std::is_same_v<std::remove_const_t<Row>, BenchRow>) {
        f(r.scene), f(r.hf_w), f(r.hf_h), f(r.rays), f(r.effective), f(r.aborted), f(r.mode);
        f(r.rayset_ms), f(r.heightfield_ms), f(r.trace_ms), f(r.histogram_ms), f(r.compare_ms);
        f(r.rays_per_s), f(r.l2_lm), f(r.noise_lm), f(r.l2_same_rays_lm), f(r.noise_from);
    } else if constexpr (std::is_same_v<std::remove_const_t<Row>, CandidateRow>) {
        f(r.scene), f(r.rays), f(r.reps), f(r.candidate_ms), f(r.heightfield_ms), f(r.trace_ms);
        f(r.histogram_ms), f(r.compare_ms), f(r.submissions), f(r.batch);
        f(r.batch_candidate_ms), f(r.batch_submissions);
    } else {
        static_assert(std::is_same_v<std::remove_const_t<Row>, SkipRow>);
        f(r.scene), f(r.skip), f(r.with_ms), f(r.without_ms), f(r.note);
    }
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
    w.put(bench_device(ctx));
    w.put(std::uint64_t(rows.size()));
    for (const Row& r : rows)
        fields(Out{w}, r);
    return w.bytes;
}

// Shares items out: rank 0 measures the first share with `measure`, the others theirs; the
// rows come back in the items' order (a share's rows in its items' order).
template <class Row, class Measure>
SharedBench<Row> shared(Farm& farm, const vk::Context& ctx, std::size_t items,
                        const Measure& measure) {
    std::vector<std::vector<Row>> by_share(items); // each share's rows at its first item
    SharedBench<Row> out;
    out.devices[0] = bench_device(ctx);
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
                            fields(In{in}, r);
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
