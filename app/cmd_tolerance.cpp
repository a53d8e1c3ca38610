// fird tolerance SCENE: how much the light moves when the part is made a little wrong or
// the source sits a little off (issue 27 item 4; compute/tolerance).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "evaluation/evaluation.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "model/tolerance_check.hpp"
#include "parse.hpp"
#include "tolerance/tolerance.hpp"
#include "vk/context.hpp"

#if FIRD_HAVE_MPI
#include "distributed/batch_farm.hpp"
#include "distributed/job.hpp"
#include "distributed/tolerance_shares.hpp"
#include "interrupt.hpp"
#include "shared_work.hpp"
#endif

namespace fird::app {

namespace {

double non_negative(const std::string& option, const std::string& text) {
    try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v) && v >= 0.0) return v;
    } catch (const std::exception&) {
    }
    throw UsageError(fmt::format("{}: '{}' is not a number >= 0", option, text));
}

std::string spread_text(const nlohmann::json& s, const char* unit) {
    if (s.is_null()) return "none (every realisation infeasible)";
    return fmt::format("median {:.4g}{}, 5 % {:.4g}{}, 95 % {:.4g}{}", s["median"].get<double>(),
                       unit, s["p5"].get<double>(), unit, s["p95"].get<double>(), unit);
}

} // namespace

void register_tolerance(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand(
        "tolerance", "Trace realisations of the luminaire with its tolerances drawn: the spread "
                     "of l2, efficiency, peak intensity and beam angle, and which tolerance "
                     "moves them most");
    struct Args {
        std::string scene, out, rays, realisations, shift, tilt, surface_rms, surface_corr,
            reflectance_sd;
        std::string backend = "gpu";
        std::uint64_t seed = 1;
        double rank_timeout = 0.0;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("SCENE", a->scene, "Scene file (TOML; its [tolerance] table gives defaults)")
        ->required();
    cmd->add_option("--realisations", a->realisations,
                    "Realisations per run (the joint run and each tolerance's own)");
    cmd->add_option("--source-shift-mm", a->shift,
                    "The source centre's standard deviation: X,Y,Z or one value for all axes");
    cmd->add_option("--source-tilt-deg", a->tilt,
                    "The source axis's standard deviation about x and about y");
    cmd->add_option("--surface-rms-mm", a->surface_rms, "A smooth random surface error's RMS");
    cmd->add_option("--surface-correlation-mm", a->surface_corr, "... and its correlation length");
    cmd->add_option("--reflectance-sd", a->reflectance_sd, "The reflectance's standard deviation");
    cmd->add_option("--rays", a->rays, "Rays per realisation (overrides [trace] rays)");
    cmd->add_option("--seed", a->seed, "Seed of the draws (each realisation its own stream)");
    cmd->add_option("--backend", a->backend, "gpu (the fast path) or cpu (the exact reference)")
        ->check(CLI::IsMember({"gpu", "cpu"}));
    cmd->add_flag("--json", a->json, "Print one JSON object");
    cmd->add_option("--out", a->out, "Write tolerance.csv, tolerance.json and tolerance.png here");
    cmd->add_option("--rank-timeout", a->rank_timeout,
                    "Under mpirun or srun: the longest wait (s) on a rank for its share of the "
                    "realisations (default: 60 s plus ten times rank 0's own share)");
    cmd->callback([&global, &run, a, cmd] {
        run = [&global, a, cmd] {
            if (cmd->count("--rank-timeout") && !(a->rank_timeout > 0.0))
                throw UsageError("--rank-timeout must be more than 0 s");
            TraceOverrides o;
            if (!a->rays.empty()) o.rays = parse_count("--rays", a->rays, 1e10);
            const Scene scene = apply_overrides(load_scene(a->scene), o);
            ToleranceDesc t = scene.tolerance;
            if (!a->realisations.empty())
                t.realisations = parse_count("--realisations", a->realisations, 1e6);
            if (!a->shift.empty()) {
                const auto parts = split_list(a->shift);
                if (parts.size() == 1)
                    t.source_shift_mm = glm::dvec3(non_negative("--source-shift-mm", parts[0]));
                else if (parts.size() == 3)
                    for (int k = 0; k < 3; ++k)
                        t.source_shift_mm[k] = non_negative("--source-shift-mm", parts[k]);
                else
                    throw UsageError("--source-shift-mm: one value or X,Y,Z");
            }
            if (!a->tilt.empty()) t.source_tilt_deg = non_negative("--source-tilt-deg", a->tilt);
            if (!a->surface_rms.empty())
                t.surface_rms_mm = non_negative("--surface-rms-mm", a->surface_rms);
            if (!a->surface_corr.empty())
                t.surface_correlation_mm =
                    non_negative("--surface-correlation-mm", a->surface_corr);
            if (!a->reflectance_sd.empty())
                t.reflectance_sd = non_negative("--reflectance-sd", a->reflectance_sd);
            if (const auto problem = tolerance_problem(t, scene.source)) {
                std::string option = "--" + problem->key;
                std::replace(option.begin(), option.end(), '_', '-');
                throw UsageError(option + ": " + problem->reason);
            }
            if (active_tolerances(t).empty())
                throw UsageError("no tolerance given: --source-shift-mm, --source-tilt-deg, "
                                 "--surface-rms-mm, --reflectance-sd or a [tolerance] table");
#if FIRD_HAVE_MPI
            // A rank other than 0 traces the shares of the realisations rank 0 sends it.
            if (global.job && global.job->rank() > 0) {
                const auto ctx = vk::Context::create(context_options(global));
                const ToleranceRun mine{.tolerances = t,
                                        .seed = a->seed,
                                        .backend = a->backend == "gpu" ? Backend::Fast
                                                                       : Backend::Reference};
                const int code = distributed::serve_shares(
                    *global.job, distributed::tolerance_worker(ctx, scene, mine));
                if (ctx.validation_errors() > 0)
                    throw std::runtime_error("Vulkan validation errors were reported (see above)");
                return code;
            }
#endif
            if (!a->out.empty()) create_output_directory(a->out); // unwritable: before tracing
            const auto ctx = vk::Context::create(context_options(global));
            ToleranceRun r{.tolerances = t,
                           .seed = a->seed,
                           .backend = a->backend == "gpu" ? Backend::Fast : Backend::Reference,
                           .scratch_dir = a->out};
#if FIRD_HAVE_MPI
            // Under mpirun: the realisations' shares go to the other ranks.
            SearchControl control;
            std::optional<distributed::Farm> farm;
            std::optional<InterruptScope> interrupts; // mpirun's SIGTERM, when a rank dies
            if (global.job && global.job->distributed()) {
                farm.emplace(*global.job, &control,
                             cmd->count("--rank-timeout") ? std::optional(a->rank_timeout)
                                                          : std::nullopt,
                             std::string());
                r.distributed = distributed::tolerance_tracing(*farm);
                interrupts.emplace(control);
            }
#endif
            if (!a->json)
                r.progress = [](const RealisationResult& row, std::size_t done, std::size_t total) {
                    std::fprintf(stderr, "\r%zu / %zu realisations (%s)   ", done, total,
                                 row.kind.c_str());
                    if (done == total) std::fprintf(stderr, "\n");
                };
            ToleranceResult result;
#if FIRD_HAVE_MPI
            if (const auto code = run_shared(farm, control, "realisations", [&] {
                    result = run_tolerance(ctx, scene, r);
                    return result.time_s;
                }))
                return *code;
#else
            result = run_tolerance(ctx, scene, r);
#endif
            if (ctx.validation_errors() > 0)
                throw std::runtime_error("Vulkan validation errors were reported (see above)");
            if (!a->out.empty()) write_tolerance_outputs(a->out, scene, result);
            const nlohmann::json j = tolerance_json(result);
            if (a->json) {
                std::printf("%s\n", j.dump(2).c_str());
                return 0;
            }
            std::printf("%s: %llu realisations, %.1f s\n", scene.name.c_str(),
                        static_cast<unsigned long long>(t.realisations), result.time_s);
            if (j.contains("l2"))
                std::printf(
                    "%s to the target: %s\n", j["metric"].get<std::string>().c_str(),
                    spread_text(j["l2"], (" " + j["metric_unit"].get<std::string>()).c_str())
                        .c_str());
            std::printf("efficiency: %s\n", spread_text(j["efficiency"], "").c_str());
            std::printf("peak intensity: %s\n", spread_text(j["peak_cd"], " cd").c_str());
            std::printf("beam angle: %s\n", spread_text(j["beam_angle_deg"], " deg").c_str());
            std::printf("moves %s most: %s\n", result.ranked_by.c_str(),
                        result.most_sensitive.empty() ? "none ranked (a tolerance had no feasible "
                                                        "realisation)"
                                                      : result.most_sensitive.c_str());
            if (!a->out.empty())
                std::printf("wrote %s/tolerance.csv, tolerance.json and tolerance.png\n",
                            a->out.c_str());
            return 0;
        };
    });
}

} // namespace fird::app
