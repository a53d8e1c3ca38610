// fird bench: run time against error for the fast path (table, CSV, plot).
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>

#include "bench/bench.hpp"
#include "commands.hpp"
#include "io/atomic_file.hpp"
#include "parse.hpp"

namespace fird::app {

void register_bench(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("bench", "Run time against error of the fast path");
    struct Args {
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
        std::string out = "bench_out";
    };
    auto a = std::make_shared<Args>();
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
    cmd->callback([&global, &run, a, cmd] {
        const bool cmd_rays_given = cmd->count("--rays") > 0;
        run = [&global, a, cmd_rays_given] {
            if (a->skips && a->candidates)
                throw UsageError("--skips and --candidates exclude each other");
            if (a->skips) {
                const auto ctx = vk::Context::create(context_options(global));
                const auto rows = run_skips_bench(ctx, a->scenes, a->reps, [](const SkipRow& r) {
                    std::fprintf(stderr, "bench --skips: %s: %s: %.1f ms with, %.1f ms without\n",
                                 r.scene.c_str(), r.skip.c_str(), r.with_ms, r.without_ms);
                });
                const std::string md = skips_markdown(rows, ctx.summary().name + " (" +
                                                                ctx.summary().driver_info + ")");
                std::printf("%s", md.c_str());
                create_output_directory(a->out);
                write_text_file(a->out + "/skips.md", md);
                return 0;
            }
            if (a->candidates) {
                const auto counts = cmd_rays_given ? parse_counts("--rays", a->rays, 4e9)
                                                   : std::vector<std::uint64_t>{0};
                if (counts.size() != 1) throw UsageError("--candidates takes one --rays count");
                const auto ctx = vk::Context::create(context_options(global));
                const auto rows = run_candidate_bench(ctx, a->scenes, counts[0], a->reps,
                                                      std::uint64_t(a->batch));
                const std::string md = candidates_markdown(
                    rows, ctx.summary().name + " (" + ctx.summary().driver_info + ")");
                std::printf("%s", md.c_str());
                create_output_directory(a->out);
                write_candidates_csv(a->out + "/candidates.csv", rows);
                return 0;
            }
            BenchOptions o;
            o.scenes = a->scenes;
            o.heightfields.clear();
            for (const auto& wh : split_list(a->heightfields)) {
                unsigned w = 0, h = 0;
                char x = 0;
                std::istringstream is(wh);
                if (!(is >> w >> x >> h) || x != 'x' || w == 0 || h == 0)
                    throw UsageError(fmt::format("--heightfields: '{}' is not WxH", wh));
                o.heightfields.emplace_back(w, h);
            }
            o.rays = parse_counts("--rays", a->rays, 4e9);
            o.modes.clear();
            for (const auto& m : split_list(a->modes)) {
                if (m != "paper" && m != "refined")
                    throw UsageError(fmt::format("--modes: '{}' is not paper or refined", m));
                o.modes.push_back(m == "paper" ? HitMode::Paper : HitMode::Refined);
            }
            if (!(a->reference_rays >= 1)) throw UsageError("--reference-rays must be >= 1");
            o.reference_rays = std::uint64_t(a->reference_rays);
            o.same_rays = a->same_rays;
            const auto ctx = vk::Context::create(context_options(global));
            const auto rows = run_bench(ctx, o, [](const BenchRow& r) {
                std::fprintf(stderr, "bench: %s %ux%u %.0e %s: trace %.1f ms, l2 %.4f lm\n",
                             r.scene.c_str(), r.hf_w, r.hf_h, double(r.rays), r.mode.c_str(),
                             r.trace_ms, r.l2_lm);
            });
            create_output_directory(a->out);
            const std::string md =
                bench_markdown(rows, ctx.summary().name + " (" + ctx.summary().driver_info + ")");
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
