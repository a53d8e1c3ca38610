// fird bench: run time against error for the fast path (table, CSV, plot); under mpirun or
// srun its rows (or scenes) measured across the ranks, each on its own device.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "bench/bench.hpp"
#include "commands.hpp"
#include "io/atomic_file.hpp"
#include "parse.hpp"

#if FIRD_HAVE_MPI
#include "distributed/batch_farm.hpp"
#include "distributed/bench_shares.hpp"
#include "distributed/job.hpp"
#include "interrupt.hpp"
#include "shared_work.hpp"
#endif

namespace fird::app {

namespace {

// The longest wait on a rank's share of a bench, unless --rank-timeout says.
constexpr double kBenchRankTimeoutS = 3600.0;

struct BenchArgs {
    std::vector<std::string> scenes{"scenes/model_a.toml", "scenes/model_b.toml",
                                    "scenes/model_c.toml"};
    std::string heightfields = "300x200,600x400,1200x800,2400x1600";
    std::string rays = "1e5,1e6,1e7";
    std::string modes = "paper,refined";
    double reference_rays = 2e6;
    bool same_rays = false;
    bool skips = false;
    bool candidates = false;
    int batch = 16;
    int reps = 5;
    double rank_timeout = 0.0;
    std::string out = "bench_out";
};

// The sweep's options from the command line (usage errors name the option).
BenchOptions sweep_options(const BenchArgs& a) {
    BenchOptions o;
    o.scenes = a.scenes;
    o.heightfields.clear();
    for (const auto& wh : split_list(a.heightfields)) {
        unsigned w = 0, h = 0;
        char x = 0;
        std::istringstream is(wh);
        if (!(is >> w >> x >> h) || x != 'x' || w == 0 || h == 0)
            throw UsageError(fmt::format("--heightfields: '{}' is not WxH", wh));
        o.heightfields.emplace_back(w, h);
    }
    o.rays = parse_counts("--rays", a.rays, 4e9);
    o.modes.clear();
    for (const auto& m : split_list(a.modes)) {
        if (m != "paper" && m != "refined")
            throw UsageError(fmt::format("--modes: '{}' is not paper or refined", m));
        o.modes.push_back(m == "paper" ? HitMode::Paper : HitMode::Refined);
    }
    if (!(a.reference_rays >= 1)) throw UsageError("--reference-rays must be >= 1");
    o.reference_rays = std::uint64_t(a.reference_rays);
    o.same_rays = a.same_rays;
    return o;
}

void sweep_progress(const BenchRow& r) {
    std::fprintf(stderr, "bench: %s %ux%u %.0e %s: trace %.1f ms, l2 %.4f lm\n", r.scene.c_str(),
                 r.hf_w, r.hf_h, double(r.rays), r.mode.c_str(), r.trace_ms, r.l2_lm);
}

void skip_progress(const SkipRow& r) {
    std::fprintf(stderr, "bench --skips: %s: %s: %.1f ms with, %.1f ms without\n", r.scene.c_str(),
                 r.skip.c_str(), r.with_ms, r.without_ms);
}

#if FIRD_HAVE_MPI
// The ranks of an MPI job sharing a bench: the farm (none in one process) and how a lost
// rank ends it.
struct BenchRanks {
    SearchControl control;
    std::optional<distributed::Farm> farm;
    std::optional<InterruptScope> interrupts; // mpirun's SIGTERM, when a rank dies
    std::optional<int> exit_code;             // set where a lost rank ended the bench

    // `shared` across the ranks (`items` names what was shared): its rows, each rank's
    // device on `devices`; nullopt, with exit_code, where a lost rank ended it.
    template <class Shared>
    auto measure(const char* items, std::string& devices, Shared shared)
        -> std::optional<decltype(shared(*farm).rows)> {
        decltype(shared(*farm).rows) rows;
        const auto t0 = std::chrono::steady_clock::now();
        exit_code = run_shared(farm, control, items, [&] {
            auto out = shared(*farm);
            devices = distributed::devices_line(out.devices);
            rows = std::move(out.rows);
            return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        });
        if (exit_code) return std::nullopt;
        return rows;
    }
};
#endif

} // namespace

void register_bench(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("bench", "Run time against error of the fast path");
    auto a = std::make_shared<BenchArgs>();
    cmd->add_option("SCENES", a->scenes, "Scene files (default: the paper's three)");
    cmd->add_option("--heightfields", a->heightfields, "Comma-separated WxH sizes");
    cmd->add_option("--rays", a->rays, "Comma-separated ray counts (1e5 style allowed)");
    cmd->add_option("--modes", a->modes, "paper, refined or both");
    cmd->add_option("--reference-rays", a->reference_rays, "Rays of the CPU reference per scene");
    cmd->add_flag("--same-rays", a->same_rays,
                  "Also compare each row with the CPU reference of its own rays (no Monte Carlo "
                  "noise: the discretization error alone)");
    cmd->add_flag("--skips", a->skips,
                  "Instead: the time each skip of the fast path saves (each switched off for the "
                  "measurement)");
    cmd->add_flag("--candidates", a->candidates,
                  "Instead: what one candidate of a search costs (rayset kept, height field "
                  "rebuilt, trace, histogram, compare), at --rays (one count; default: the "
                  "scene's); writes candidates.csv");
    cmd->add_option("--batch", a->batch,
                    "With --candidates: also the cost per candidate when K are traced together "
                    "(several per submission; 1: singles only)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("--reps", a->reps, "Runs per measurement of --skips and --candidates")
        ->check(CLI::Range(1, 100));
    cmd->add_option("--out", a->out, "Directory for bench.csv, bench.md and bench.png");
    cmd->add_option("--rank-timeout", a->rank_timeout,
                    "Under mpirun or srun: the longest wait, in seconds, for a rank's share "
                    "(default 3600: shares are contiguous, rank 0's the cheapest rows)");
    cmd->callback([&global, &run, a, cmd] {
        const bool cmd_rays_given = cmd->count("--rays") > 0;
        const bool rank_timeout_given = cmd->count("--rank-timeout") > 0;
        run = [&global, a, cmd_rays_given, rank_timeout_given]() -> int {
            if (a->skips && a->candidates)
                throw UsageError("--skips and --candidates exclude each other");
            if (rank_timeout_given && !(a->rank_timeout > 0.0))
                throw UsageError("--rank-timeout must be more than 0 s");
            // What to measure, from the command line alone (every rank of a job reads it).
            std::uint64_t candidate_rays = 0;
            if (a->candidates) {
                const auto counts = cmd_rays_given ? parse_counts("--rays", a->rays, 4e9)
                                                   : std::vector<std::uint64_t>{0};
                if (counts.size() != 1) throw UsageError("--candidates takes one --rays count");
                candidate_rays = counts[0];
            }
            const BenchOptions sweep =
                a->skips || a->candidates ? BenchOptions{} : sweep_options(*a);
            const auto ctx = vk::Context::create(context_options(global));
            std::string devices = bench_device(ctx);
#if FIRD_HAVE_MPI
            const distributed::BenchWork work{.kind = a->skips ? distributed::BenchKind::Skips
                                                      : a->candidates
                                                          ? distributed::BenchKind::Candidates
                                                          : distributed::BenchKind::Sweep,
                                              .sweep = sweep,
                                              .scenes = a->scenes,
                                              .rays = candidate_rays,
                                              .batch = std::uint64_t(a->batch),
                                              .reps = a->reps};
            // A rank other than 0 measures the shares rank 0 sends it, on its own device.
            if (global.job && global.job->rank() > 0) {
                const int code = distributed::serve_shares(
                    *global.job, distributed::bench_worker(ctx, global.job->rank(), work));
                if (ctx.validation_errors() > 0)
                    throw std::runtime_error("Vulkan validation errors were reported (see above)");
                return code;
            }
            BenchRanks ranks;
            if (global.job && global.job->distributed()) {
                // A bound of its own: the farm's default (60 s plus ten times rank 0's own
                // share) is too short where the sweep's first rows, rank 0's, are its
                // cheapest (the smallest height field and ray count).
                ranks.farm.emplace(*global.job, &ranks.control,
                                   rank_timeout_given ? a->rank_timeout : kBenchRankTimeoutS,
                                   std::string());
                ranks.interrupts.emplace(ranks.control);
            }
#else
            (void)rank_timeout_given;
#endif
            if (a->skips) {
                std::vector<SkipRow> rows;
#if FIRD_HAVE_MPI
                if (ranks.farm) {
                    auto shared = ranks.measure("scenes", devices, [&](distributed::Farm& farm) {
                        return distributed::shared_skips(farm, ctx, work);
                    });
                    if (!shared) return *ranks.exit_code;
                    rows = std::move(*shared);
                } else
#endif
                    rows = run_skips_bench(ctx, a->scenes, a->reps, skip_progress);
                const std::string md = skips_markdown(rows, devices);
                std::printf("%s", md.c_str());
                create_output_directory(a->out);
                write_text_file(a->out + "/skips.md", md);
                return 0;
            }
            if (a->candidates) {
                std::vector<CandidateRow> rows;
#if FIRD_HAVE_MPI
                if (ranks.farm) {
                    auto shared = ranks.measure("scenes", devices, [&](distributed::Farm& farm) {
                        return distributed::shared_candidates(farm, ctx, work);
                    });
                    if (!shared) return *ranks.exit_code;
                    rows = std::move(*shared);
                } else
#endif
                    rows = run_candidate_bench(ctx, a->scenes, candidate_rays, a->reps,
                                               std::uint64_t(a->batch));
                const std::string md = candidates_markdown(rows, devices);
                std::printf("%s", md.c_str());
                create_output_directory(a->out);
                write_candidates_csv(a->out + "/candidates.csv", rows);
                return 0;
            }
            std::vector<BenchRow> rows;
#if FIRD_HAVE_MPI
            if (ranks.farm) {
                auto shared = ranks.measure("rows", devices, [&](distributed::Farm& farm) {
                    return distributed::shared_sweep(farm, ctx, work);
                });
                if (!shared) return *ranks.exit_code;
                rows = std::move(*shared);
            } else
#endif
                rows = run_bench(ctx, sweep, sweep_progress);
            create_output_directory(a->out);
            const std::string md = bench_markdown(rows, devices);
            std::printf("%s", md.c_str());
            write_bench_csv(a->out + "/bench.csv", rows);
            write_text_file(a->out + "/bench.md", md);
            write_bench_plot(a->out + "/bench.png", rows);
            std::fprintf(stderr, "bench: wrote %s/bench.csv, bench.md, bench.png\n",
                         a->out.c_str());
            return 0;
        };
    });
}

} // namespace fird::app
