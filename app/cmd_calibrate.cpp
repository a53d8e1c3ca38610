// fird calibrate rays|semivariogram SCENE: how many rays are enough (Table 1) and the
// smallest useful step per parameter (the semivariogram, Figure 8).
#include <cstdio>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "calibrate/calibration_report.hpp"
#include "commands.hpp"
#include "interrupt.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "parse.hpp"
#include "progress.hpp"
#include "vk/context.hpp"

#if FIRD_HAVE_MPI
#include "distributed/batch_farm.hpp"
#include "distributed/calibration_shares.hpp"
#include "distributed/job.hpp"
#include "distributed/semivariogram_shares.hpp"
#include "shared_work.hpp"
#endif

namespace fird::app {

namespace {

struct RaysArgs {
    std::string scene, counts = "1e3,1e4,1e5,1e6,1e7", desired_rays, out;
    std::uint32_t runs = 100;
    std::uint64_t seed = 1;
    std::optional<double> rank_timeout_s; // --rank-timeout (under mpirun)
    bool json = false;
};

struct SemivariogramArgs {
    std::string scene, parameter = "all", rays = "1e6", out, write_steps;
    StepRule step_rule = StepRule::Resolvable;
    std::uint32_t points = 101;
    std::uint64_t seed = 1;
    bool json = false;
    std::optional<double> rank_timeout_s; // --rank-timeout (under mpirun)
};

Scene load_scene_with_target(const std::string& path) {
    Scene scene = load_scene(path);
    if (scene.target.kind == TargetDesc::Kind::None)
        throw std::invalid_argument(fmt::format(
            "{}: [target] is missing: calibration compares with the desired far field", path));
    return scene;
}

vk::Context make_context(const GlobalOptions& g) {
    return vk::Context::create(context_options(g));
}

void check_validation(const vk::Context& ctx) {
    if (ctx.validation_errors() > 0)
        throw std::runtime_error("Vulkan validation errors were reported (see above)");
}

int run_rays(const GlobalOptions& global, const RaysArgs& a) {
    RaysTableOptions o{
        .counts = parse_counts("--counts", a.counts, 4e9), .runs = a.runs, .seed = a.seed};
    if (!a.desired_rays.empty())
        o.desired_rays = parse_count("--desired-rays", a.desired_rays, 4e9);
    if (a.rank_timeout_s && !(*a.rank_timeout_s > 0.0))
        throw UsageError("--rank-timeout must be more than 0 s");
    const Scene scene = load_scene_with_target(a.scene);
    const auto ctx = make_context(global);
#if FIRD_HAVE_MPI
    // A rank other than 0 traces the pairs of runs rank 0 sends it.
    if (global.job && global.job->rank() > 0) {
        const int code =
            distributed::serve_shares(*global.job, distributed::calibration_worker(ctx, scene, o));
        check_validation(ctx);
        return code;
    }
#endif
    ProgressLine progress;
    SearchControl control;
    RaysTable table;
#if FIRD_HAVE_MPI
    // Under mpirun: each row's pairs of runs shared among the ranks.
    std::optional<distributed::Farm> farm;
    if (global.job && global.job->distributed()) {
        farm.emplace(*global.job, &control, a.rank_timeout_s, std::string());
        o.distributed = distributed::calibration_tracing(*farm);
    }
#endif
    const auto calibrate = [&] {
        const InterruptScope interrupts(control);
        table = calibrate_rays(
            ctx, scene, o, &control, [&](std::size_t c, std::uint32_t run, double l2) {
                progress.show(fmt::format(
                    "calibrate rays: {:.0e} rays, run {} of {}, l2 {:.4g} lm | {}",
                    double(o.counts[c]), run + 1, o.runs, l2, clock_time(progress.elapsed_s())));
            });
        return table.time_s;
    };
#if FIRD_HAVE_MPI
    if (const auto code = run_shared(farm, control, "pairs of runs", calibrate)) return *code;
#else
    calibrate();
#endif
    progress.finish();
    check_validation(ctx);
    if (!a.out.empty()) write_rays_table(a.out, table, scene.name);
    if (a.json)
        std::printf("%s\n", rays_table_json(table).dump(2).c_str());
    else
        std::printf("%s", rays_table_markdown(table, scene.name).c_str());
    return 0;
}

int run_semivariogram(const GlobalOptions& global, const SemivariogramArgs& a) {
    if (a.rank_timeout_s && !(*a.rank_timeout_s > 0.0))
        throw UsageError("--rank-timeout must be more than 0 s");
    SemivariogramOptions o{.points = a.points,
                           .rays = parse_count("--rays", a.rays, 4e9),
                           .seed = a.seed,
                           .step_rule = a.step_rule};
    if (a.points < 3)
        throw UsageError(fmt::format("--points {}: a semivariogram needs at least 3", a.points));
    if (a.parameter != "all") o.parameters = split_list(a.parameter);
    const Scene scene = load_scene_with_target(a.scene);
    for (const std::string& name : o.parameters)
        if (!scene.reflector.optimize.count(name))
            throw UsageError(
                fmt::format("--parameter {}: not in {}'s [reflector.optimize]", name, scene.path));
    const auto ctx = make_context(global);
#if FIRD_HAVE_MPI
    // A rank other than 0 traces the series' points rank 0 sends it.
    if (global.job && global.job->rank() > 0) {
        const int code = distributed::serve_shares(
            *global.job, distributed::semivariogram_worker(ctx, scene, o));
        check_validation(ctx);
        return code;
    }
#endif
    ProgressLine progress;
    SearchControl control;
    SemivariogramResult result;
#if FIRD_HAVE_MPI
    // Under mpirun: each series' points shared among the ranks.
    std::optional<distributed::Farm> farm;
    if (global.job && global.job->distributed()) {
        farm.emplace(*global.job, &control, a.rank_timeout_s, std::string());
        o.distributed = distributed::semivariogram_tracing(*farm);
    }
#endif
    const auto calibrate = [&] {
        const InterruptScope interrupts(control);
        result = calibrate_semivariogram(
            ctx, scene, o, &control, [&](std::size_t, std::uint32_t j, double l2) {
                progress.show(
                    fmt::format("calibrate semivariogram: point {} of {}, l2 {:.4g} lm | {}", j + 1,
                                o.points, l2, clock_time(progress.elapsed_s())));
            });
        return result.time_s;
    };
#if FIRD_HAVE_MPI
    if (const auto code = run_shared(farm, control, "series points", calibrate)) return *code;
#else
    calibrate();
#endif
    progress.finish();
    check_validation(ctx);
    if (!a.out.empty()) write_semivariograms(a.out, result, scene.name);
    if (!a.write_steps.empty())
        write_text_file(a.write_steps,
                        fmt::format("# {} with the steps of fird calibrate semivariogram ({:.0e} "
                                    "rays, {} points)\n",
                                    scene.name, double(o.rays), o.points) +
                            scene_to_toml(scene_with_steps(scene, result)));
    if (a.json) {
        std::printf("%s\n", semivariogram_json(result).dump(2).c_str());
    } else {
        std::printf("%s",
                    fmt::format("{}: semivariograms of l2 ({:.0e} rays, {} points, {:.1f} s); "
                                "noise: variance of l2 {:.3g} lm^2 over {} traces of the desired "
                                "reflector\n",
                                scene.name, double(o.rays), o.points, result.time_s,
                                result.noise_variance_l2, o.noise_runs)
                        .c_str());
        for (const ParameterSemivariogram& p : result.parameters)
            std::printf("%s: %s model, nugget %.4g, sill %.4g, range %.4g; recommended step "
                        "%.4g, resolvable step (95 %% ordered, same rays) %s; calibrated step "
                        "(%s) %.4g\n",
                        p.parameter.c_str(), variogram_model_name(p.model.model), p.model.nugget,
                        p.model.sill, p.model.range, p.recommended_step,
                        p.resolvable_step ? fmt::format("{:.4g}", *p.resolvable_step).c_str()
                                          : "none",
                        step_rule_name(a.step_rule), calibrated_step(p, a.step_rule));
    }
    return 0;
}

} // namespace

void register_calibrate(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("calibrate", "Calibrate before a search: rays and steps");
    cmd->require_subcommand(1);

    auto* rays =
        cmd->add_subcommand("rays", "l2 of independent simulations against rays (Table 1)");
    auto r = std::make_shared<RaysArgs>();
    rays->add_option("SCENE", r->scene, "Scene file (TOML) with a [target]")->required();
    rays->add_option("--counts", r->counts, "Ray counts, e.g. 1e3,1e4,1e5,1e6,1e7");
    rays->add_option("--runs", r->runs, "Simulations per count, each with fresh rays")
        ->check(CLI::Range(1.0, 1e6));
    rays->add_option("--desired-rays", r->desired_rays,
                     "Rays of the desired reflector's trace (default: 10 x the largest count)");
    rays->add_option("--seed", r->seed, "Seed of the calibration's rays")
        ->check(CLI::NonNegativeNumber);
    rays->add_flag("--json", r->json, "Print one JSON object");
    rays->add_option("--out", r->out, "Write table1.csv, table1.md, table1.png here");
    rays->add_option("--rank-timeout", r->rank_timeout_s,
                     "Under mpirun or srun: the longest wait (s) on a rank for its share of a "
                     "row's runs (default: 60 s plus ten times rank 0's own share)");
    rays->callback([&global, &run, r] { run = [&global, r] { return run_rays(global, *r); }; });

    auto* sv = cmd->add_subcommand("semivariogram",
                                   "The semivariogram of l2 along each parameter (Figure 8)");
    auto s = std::make_shared<SemivariogramArgs>();
    sv->add_option("SCENE", s->scene, "Scene file (TOML) with [reflector.optimize] and a [target]")
        ->required();
    sv->add_option("--parameter", s->parameter, "A parameter of [reflector.optimize], or all");
    sv->add_option("--points", s->points, "Values along the parameter (K >= 3)")
        ->check(CLI::NonNegativeNumber);
    sv->add_option("--rays", s->rays, "Rays per point");
    sv->add_option("--seed", s->seed, "Seed of the calibration's rays")
        ->check(CLI::NonNegativeNumber);
    sv->add_flag("--json", s->json, "Print one JSON object");
    sv->add_option(
        "--out", s->out,
        "Write series.csv, semivariogram.csv, resolution.csv, semivariogram_NAME.png here");
    sv->add_option("--write-steps", s->write_steps,
                   "Write the scene with the calibrated [reflector.optimize] steps to this file");
    sv->add_option("--step-rule", s->step_rule,
                   "Steps --write-steps writes: resolvable (default: the smallest step whose two "
                   "points a search orders correctly 95 % of the time on the same rays) or "
                   "range (the paper's lower bound, never below the resolvable step)")
        ->transform(CLI::CheckedTransformer(std::map<std::string, StepRule>{
            {"range", StepRule::Range}, {"resolvable", StepRule::Resolvable}}));
    sv->add_option("--rank-timeout", s->rank_timeout_s,
                   "Under mpirun or srun: the longest wait (s) on a rank for its share of a "
                   "series' points (default: 60 s plus ten times rank 0's own share)");
    sv->callback(
        [&global, &run, s] { run = [&global, s] { return run_semivariogram(global, *s); }; });
}

} // namespace fird::app
