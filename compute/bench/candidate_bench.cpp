// fird bench --candidates: what one candidate of a search costs, as the optimizer pays it.
#include <algorithm>
#include <chrono>
#include <sstream>

#include <fmt/format.h>

#include "bench/bench.hpp"
#include "evaluation/desired_farfield.hpp"
#include "evaluation/evaluator.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "optimize/search.hpp"

namespace fird {

std::vector<CandidateRow> run_candidate_bench(const vk::Context& ctx,
                                              const std::vector<std::string>& paths,
                                              std::uint64_t rays, int reps, std::uint64_t batch) {
    std::vector<CandidateRow> rows;
    for (const std::string& path : paths) {
        Scene s = load_scene(path);
        if (rays) s.trace.rays = rays;
        Evaluator ev(ctx, s, scene_fidelity(s));
        // Two reflectors alternate, so every candidate rebuilds its height field as a
        // search's do (the scene's and its target's; one reflector alone: rebuilt anyway).
        const ReflectorDesc a = s.reflector;
        const bool has_target = s.target.kind == TargetDesc::Kind::Reflector;
        const ReflectorDesc b = has_target ? target_reflector(s) : s.reflector;
        FastPathSkips skips;
        skips.keep_heightfield = has_target;
        ev.set_skips(skips);
        const CandidateResult first = ev.evaluate(a); // the rayset, pipelines and caches warm
        if (s.target.kind != TargetDesc::Kind::None)
            ev.set_desired(desired_farfield(ctx, s, first.farfield_lm).farfield);
        CandidateRow row{.scene = s.name, .rays = s.trace.rays, .reps = reps};
        std::vector<double> wall, hf, trace, hist, compare, submissions;
        for (int k = 0; k < reps; ++k) {
            const std::uint64_t submitted = ctx.submissions();
            const CandidateResult r = ev.evaluate(k % 2 ? a : b);
            submissions.push_back(double(ctx.submissions() - submitted));
            wall.push_back(r.wall_ms);
            hf.push_back(r.run.timings.heightfield_ms);
            trace.push_back(r.run.timings.trace_ms);
            hist.push_back(r.run.timings.histogram_ms);
            compare.push_back(r.run.timings.compare_ms);
        }
        row.candidate_ms = median_ms(wall);
        row.heightfield_ms = median_ms(hf);
        row.trace_ms = median_ms(trace);
        row.histogram_ms = median_ms(hist);
        row.compare_ms = median_ms(compare);
        row.submissions = std::uint64_t(median_ms(submissions));
        if (batch > 1) {
            // K candidates, the two reflectors alternating, each height field rebuilt (a
            // batch's slot would otherwise keep its reflector from the batch before).
            std::vector<ReflectorDesc> list;
            for (std::uint64_t k = 0; k < batch; ++k)
                list.push_back(k % 2 ? a : b);
            skips.keep_heightfield = false;
            ev.set_skips(skips);
            (void)ev.evaluate_batch(list); // the batch's height fields and far fields made
            std::vector<double> batch_wall, batch_submissions;
            for (int k = 0; k < reps; ++k) {
                const std::uint64_t submitted = ctx.submissions();
                const auto t0 = std::chrono::steady_clock::now();
                (void)ev.evaluate_batch(list);
                batch_wall.push_back(
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count() /
                    double(batch));
                batch_submissions.push_back(double(ctx.submissions() - submitted));
            }
            row.batch = batch;
            row.batch_candidate_ms = median_ms(batch_wall);
            row.batch_submissions = std::uint64_t(median_ms(batch_submissions));
        }
        rows.push_back(row);
    }
    return rows;
}

std::string candidates_markdown(const std::vector<CandidateRow>& rows, const std::string& device) {
    const bool ranks =
        std::any_of(rows.begin(), rows.end(), [](const CandidateRow& r) { return r.rank > 0; });
    std::string out = fmt::format(
        "Device: {}\n\n| scene | rays | candidate ms | height field ms | trace ms | histogram ms | "
        "compare ms | submissions | batch K | ms per candidate in batches of K | submissions "
        "per batch |{}\n|---|---|---|---|---|---|---|---|---|---|---|{}\n",
        device, ranks ? " rank |" : "", ranks ? "---|" : "");
    for (const CandidateRow& r : rows)
        out += fmt::format(
            "| {} | {:.0e} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {} | {} | {} | {} |{}\n",
            r.scene, double(r.rays), r.candidate_ms, r.heightfield_ms, r.trace_ms, r.histogram_ms,
            r.compare_ms, r.submissions, r.batch,
            r.batch > 1 ? fmt::format("{:.1f}", r.batch_candidate_ms) : "–",
            r.batch > 1 ? fmt::format("{}", r.batch_submissions) : "–",
            ranks ? fmt::format(" {} |", r.rank) : "");
    return out;
}

void write_candidates_csv(const std::string& path, const std::vector<CandidateRow>& rows) {
    std::ostringstream csv;
    csv << "scene,rays,reps,candidate_ms,heightfield_ms,trace_ms,histogram_ms,compare_ms,"
           "submissions,batch,batch_candidate_ms,batch_submissions,rank\n";
    for (const CandidateRow& r : rows)
        csv << fmt::format("\"{}\",{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{},{},{:.3f},{},{}\n",
                           r.scene, r.rays, r.reps, r.candidate_ms, r.heightfield_ms, r.trace_ms,
                           r.histogram_ms, r.compare_ms, r.submissions, r.batch,
                           r.batch_candidate_ms, r.batch_submissions, r.rank);
    write_text_file(path, csv.str());
}

} // namespace fird
