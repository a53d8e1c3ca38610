#include "bench.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/evaluator.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "optimize/search.hpp"
#include "plot/chart.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {

namespace {

// The seed stream of a row's replicate trace (stream_seed of the scene's seed).
constexpr std::uint64_t kReplicateStream = 9000;

} // namespace

std::string bench_device(const vk::Context& ctx) {
    return ctx.summary().name + " (" + ctx.summary().driver_info + ")";
}

double median_ms(std::vector<double> timings) {
    std::sort(timings.begin(), timings.end());
    return timings.empty() ? 0.0 : timings[timings.size() / 2];
}

std::size_t bench_row_count(const BenchOptions& o) {
    return o.scenes.size() * o.heightfields.size() * o.rays.size() * o.modes.size();
}

std::vector<BenchRow> run_bench(const vk::Context& ctx, const BenchOptions& o,
                                const std::function<void(const BenchRow&)>& progress) {
    std::vector<BenchRow> rows;
    const std::size_t per_scene = o.heightfields.size() * o.rays.size() * o.modes.size();
    std::size_t row = 0; // the sweep's row index
    for (const std::string& path : o.scenes) {
        // A scene none of whose rows are asked for is not read (nor its reference traced).
        if (row + per_scene <= o.first_row || row >= o.last_row) {
            row += per_scene;
            continue;
        }
        const Scene base = load_scene(path);
        // One reference per scene (independent rays): its far field and the cell
        // probabilities of the multinomial noise.
        const auto ref = trace_reference(base.source, Surface::make(base.reflector, base.holder),
                                         {.rays = o.reference_rays,
                                          .seed = base.trace.seed + 1000,
                                          .sampler = SamplerKind::Random,
                                          .max_bounces = base.trace.max_bounces,
                                          .bounce_policy = base.trace.bounce_policy,
                                          .farfield_w = base.trace.farfield_w,
                                          .farfield_h = base.trace.farfield_h,
                                          .material = base.reflector.material,
                                          .direct = base.trace.direct});
        const double multinomial = multinomial_noise_lm2_times_rays(
            ref.farfield, base.source.flux_lm, base.optimize.metric);
        // The reference traced with the fast path's own rays (same seed and sampler), once
        // per ray count: the l2 to it has no Monte Carlo noise, only the discretization
        // of the surface (and rays that float rounding sends another way).
        const Surface surface = Surface::make(base.reflector, base.holder);
        std::map<std::uint64_t, FarField> same_rays;
        const auto same_rays_reference = [&](std::uint64_t n) -> const FarField& {
            auto it = same_rays.find(n);
            if (it != same_rays.end()) return it->second;
            auto r = trace_reference(base.source, surface,
                                     {.rays = n,
                                      .seed = base.trace.seed,
                                      .sampler = base.trace.sampler,
                                      .max_bounces = base.trace.max_bounces,
                                      .bounce_policy = base.trace.bounce_policy,
                                      .farfield_w = base.trace.farfield_w,
                                      .farfield_h = base.trace.farfield_h,
                                      .material = base.reflector.material,
                                      .direct = base.trace.direct});
            return same_rays.emplace(n, std::move(r.farfield)).first->second;
        };
        for (const auto& [w, h] : o.heightfields)
            for (std::uint64_t n : o.rays)
                for (HitMode mode : o.modes) {
                    if (const std::size_t k = row++; k < o.first_row || k >= o.last_row) continue;
                    Scene s = base;
                    s.trace.heightfield_w = w;
                    s.trace.heightfield_h = h;
                    s.trace.rays = n;
                    s.trace.hit_mode = mode;
                    // Through the evaluation seam, as a search evaluates a candidate.
                    Evaluator evaluator(ctx, s, scene_fidelity(s));
                    evaluator.set_desired(ref.farfield);
                    const CandidateResult result = evaluator.evaluate(s.reflector);
                    const FastRun& run = result.run;
                    BenchRow r{.scene = base.name,
                               .hf_w = w,
                               .hf_h = h,
                               .rays = n,
                               .effective = run.tally.emitted - run.tally.discarded,
                               .aborted = run.aborted,
                               .mode = mode == HitMode::Paper ? "paper" : "refined",
                               .rayset_ms = run.timings.rayset_ms,
                               .heightfield_ms = run.timings.heightfield_ms,
                               .trace_ms = run.timings.trace_ms,
                               .histogram_ms = run.timings.histogram_ms,
                               .compare_ms = run.timings.compare_ms};
                    r.l2_lm = *result.l2_lm;
                    if (o.same_rays) {
                        evaluator.set_desired(same_rays_reference(n));
                        r.l2_same_rays_lm = evaluator.compare();
                    }
                    // The noise of the sampler this row runs: the multinomial formula for
                    // independent rays; for any other (the stratified default is quieter)
                    // measured: a replicate trace with another seed, half of whose squared
                    // l2 to this row's far field is the row's noise variance (one pair is
                    // enough: the l2 over ~1e6 cells scatters by under 1 %). The reference's
                    // own noise is multinomial (it runs the random sampler).
                    double row_noise_lm2 = multinomial / double(n);
                    if (s.trace.sampler != SamplerKind::Random) {
                        const FarField first = evaluator.farfield();
                        evaluator.set_seed(stream_seed(s.trace.seed, kReplicateStream, ~0ull));
                        (void)evaluator.evaluate(s.reflector);
                        const double d =
                            farfield_distance(first, evaluator.farfield(), evaluator.metric());
                        row_noise_lm2 = 0.5 * d * d;
                    }
                    r.noise_from =
                        s.trace.sampler == SamplerKind::Random ? "multinomial" : "replicate";
                    r.noise_lm = std::sqrt(row_noise_lm2 + multinomial / double(o.reference_rays));
                    r.rays_per_s = r.trace_ms > 0 ? double(r.effective) / (r.trace_ms * 1e-3) : 0.0;
                    rows.push_back(r);
                    if (progress) progress(r);
                }
    }
    return rows;
}

std::string bench_markdown(const std::vector<BenchRow>& rows, const std::string& device) {
    const bool ranks =
        std::any_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.rank > 0; });
    std::string s = fmt::format("Device: {}\n\n", device);
    s += "| scene | height field | rays | mode | rayset ms | height field ms | trace ms | "
         "histogram ms | compare ms | M rays/s | l2 lm | noise lm | l2/noise | "
         "l2 same rays lm | aborted | noise from |" +
         std::string(ranks ? " rank |\n" : "\n");
    s += "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|" +
         std::string(ranks ? "---|\n" : "\n");
    for (const BenchRow& r : rows)
        s += fmt::format(
                 "| {} | {}x{} | {:.0e} | {} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | {:.1f} | "
                 "{:.2f} | {:.4f} | {:.4f} | {:.2f} | {} | {} | {} |",
                 r.scene, r.hf_w, r.hf_h, double(r.rays), r.mode, r.rayset_ms, r.heightfield_ms,
                 r.trace_ms, r.histogram_ms, r.compare_ms, r.rays_per_s * 1e-6, r.l2_lm, r.noise_lm,
                 r.noise_lm > 0 ? r.l2_lm / r.noise_lm : 0.0,
                 r.l2_same_rays_lm >= 0 ? fmt::format("{:.4f}", r.l2_same_rays_lm) : "-", r.aborted,
                 r.noise_from) +
             (ranks ? fmt::format(" {} |\n", r.rank) : std::string("\n"));
    return s;
}

void write_bench_csv(const std::string& path, const std::vector<BenchRow>& rows) {
    std::string text =
        "scene,heightfield_w,heightfield_h,rays,effective,mode,rayset_ms,heightfield_ms,"
        "trace_ms,histogram_ms,compare_ms,rays_per_s,l2_lm,noise_lm,l2_same_rays_lm,aborted,"
        "noise_from,rank\n";
    for (const BenchRow& r : rows)
        text += fmt::format("{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.1f},{:.6g},{:."
                            "6g},{},{},{},{}\n",
                            r.scene, r.hf_w, r.hf_h, r.rays, r.effective, r.mode, r.rayset_ms,
                            r.heightfield_ms, r.trace_ms, r.histogram_ms, r.compare_ms,
                            r.rays_per_s, r.l2_lm, r.noise_lm,
                            r.l2_same_rays_lm >= 0 ? fmt::format("{:.6g}", r.l2_same_rays_lm) : "",
                            r.aborted, r.noise_from, r.rank);
    write_text_file(path, text);
}

void write_bench_plot(const std::string& path, const std::vector<BenchRow>& rows) {
    plot::Chart chart{.title = "Run time against error",
                      .x = {"trace stage time (ms)", plot::Scale::Log},
                      .y = {"l2 to the reference far field (lm)", plot::Scale::Log}};
    for (const char* mode : {"paper", "refined"}) {
        plot::Series s{.kind = plot::Series::Kind::Points,
                       .label = std::string(mode) + " hit mode",
                       .colour = plot::palette(mode[0] == 'p' ? 1 : 0)};
        for (const BenchRow& r : rows)
            if (r.mode == mode) {
                s.x.push_back(std::max(r.trace_ms, 1e-3));
                s.y.push_back(std::max(r.l2_lm, 1e-9));
            }
        if (!s.x.empty()) chart.series.push_back(std::move(s));
    }
    plot::write_chart_png(path, chart, 960, 600);
}

} // namespace fird
