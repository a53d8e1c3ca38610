// fird optimize SCENE: search the reflector's parameters for the desired far field.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include "commands.hpp"
#include "export/export_modules.hpp"
#include "interrupt.hpp"
#include "io/atomic_file.hpp"
#include "io/program_files.hpp"
#include "io/scene_file.hpp"
#include "optimize/cluster_job.hpp"
#include "optimize/history_csv.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/press_constraints.hpp"
#include "optimize/search.hpp"
#include "optimize/search_report.hpp"
#include "optimize/search_start.hpp"
#include "parse.hpp"
#include "progress.hpp"
#include "report/manufacturability.hpp"
#include "resume_record.hpp"
#include "vk/context.hpp"

#if FIRD_HAVE_MPI
#include "distributed/batch_farm.hpp"
#include "distributed/job.hpp"
#include "distributed/search_shares.hpp"
#include "shared_work.hpp"
#endif

namespace fird::app {

namespace {

struct OptimizeArgs {
    std::string scene, method, rays, out, resume, backend, start = "scene";
    std::uint64_t max_evals = 0, seed = 0;
    double threshold = -1.0, rank_timeout = 0.0;
    bool json = false, refine = false;
    bool job_script = false; // write the folder's run.sh and slurm.sh instead of searching
    ClusterShape shape;
};

// The settings a search was started with (search_options_json), and what else its result
// depends on (resume_record.hpp): kept beside its history so that --resume continues the
// very same search.
nlohmann::json settings_json(const SearchSettings& s, const Scene& scene,
                             const vk::DeviceSummary& device, const SearchRequest& request) {
    nlohmann::json j = search_options_json(s, scene, request.start_report);
    j["depends_on"] = depends_on_record(scene, device);
    return j;
}

struct Resumed {
    SearchSettings settings;
    nlohmann::json depends_on; // checked against the device once it is open
    nlohmann::json start;      // where the search began (absent: the scene's reflector)
};

// The recorded settings, once the scene's text, the files it names and the program are
// found unchanged.
Resumed resumed_settings(const std::string& dir, const Scene& scene) {
    const std::string path = (std::filesystem::path(dir) / "options.json").string();
    std::ifstream in(path);
    if (!in)
        throw std::runtime_error(fmt::format(
            "--resume {}: no options.json there (not the --out directory of a search)", dir));
    nlohmann::json j;
    try {
        in >> j;
        if (j.at("scene").get<std::string>() != scene_to_toml(scene))
            throw std::runtime_error(
                fmt::format("--resume {}: {} has changed since the search began", dir, scene.path));
        const nlohmann::json depends_on = j.value("depends_on", nlohmann::json());
        check_program_and_files(dir, depends_on, scene);
        SearchSettings s;
        s.method = method_from_name(j.at("method").get<std::string>()).value();
        s.rays = j.at("rays").get<std::vector<std::uint64_t>>();
        s.threshold_lm = j.at("threshold_lm").get<double>();
        s.max_evaluations = j.at("max_evaluations").get<std::uint64_t>();
        s.seed = j.at("seed").get<std::uint64_t>();
        s.refine = j.value("refine", false); // absent: recorded before --refine existed
        // Absent: recorded before --backend existed (the fast path).
        s.backend = j.value("backend", "gpu") == "cpu" ? Backend::Reference : Backend::Fast;
        return {s, depends_on, j.value("start", nlohmann::json())};
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
    } catch (const std::bad_optional_access&) {
        throw std::runtime_error(fmt::format("{}: unknown method", path));
    }
}

// The best reflector as the part: reflector.step and .stl (as fird export --cad, default
// tolerance) and the press's report beside them. A search's result stands without them: a
// surface OpenCASCADE cannot fit is a note, not a failed search.
void write_best_part(const std::string& out, const Scene& scene, const SearchResult& r) {
    if (!r.best) return;
    const ParameterSpace space = parameter_space(scene);
    const ReflectorDesc best = space.reflector(scene.reflector, r.history[*r.best].x);
    const Surface surface = Surface::make(best, scene.holder);
    (void)write_manufacturability(out, surface, best.constraints);
    try {
        (void)cad_exports().cad(surface, CadOptions{}, out);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fird: note: %s: the best reflector's CAD was not written: %s\n",
                     out.c_str(), e.what());
    }
}

#if FIRD_HAVE_MPI
// A rank other than 0 of an MPI job: traces the shares of the search's batches that rank 0
// sends it (the same scene, read from the same path), until rank 0 says the search is over.
int serve_search(const GlobalOptions& global, const OptimizeArgs& a) {
    const Scene scene = load_scene(a.scene);
    const auto ctx = vk::Context::create(context_options(global));
    PointTracer tracer(ctx, scene);
    const int code = distributed::serve_shares(*global.job, distributed::search_worker(tracer));
    if (ctx.validation_errors() > 0)
        throw std::runtime_error("Vulkan validation errors were reported (see above)");
    return code;
}
#endif

// The scene's search settings with the command line's options over them; a usage error for
// options that do not go together.
SearchSettings requested_settings(const Scene& scene, const OptimizeArgs& a, const CLI::App& cmd) {
    SearchSettings settings = search_settings(scene);
    if (!a.method.empty()) settings.method = *method_from_name(a.method);
    if (!a.rays.empty()) settings.rays = parse_counts("--rays", a.rays, 4e9);
    if (cmd.count("--max-evals")) settings.max_evaluations = a.max_evals;
    if (cmd.count("--threshold")) settings.threshold_lm = a.threshold;
    if (cmd.count("--seed")) settings.seed = a.seed;
    settings.refine = a.refine;
    if (a.backend == "cpu") settings.backend = Backend::Reference;
    if (settings.refine && settings.method != SearchMethod::Auto &&
        settings.method != SearchMethod::Grid)
        throw UsageError("--refine follows a lattice method: --method auto or grid");
    if (settings.max_evaluations == 0) throw UsageError("--max-evals must be at least 1");
    if (!(settings.threshold_lm >= 0.0))
        throw UsageError("--threshold must be >= 0 (0: never stop early)");
    if (settings.method != SearchMethod::Auto && settings.rays.size() > 1)
        settings.rays = {settings.rays.back()};
    if (a.start == "tailored")
        if (const auto why = tailored_start_refusal(scene))
            throw UsageError(fmt::format("--start tailored: {}", *why));
    return settings;
}

// fird optimize ... --job-script: the search's folder gets the scene and the scripts that
// run the search elsewhere (optimize/cluster_job.hpp), with the options given here.
int write_job(const GlobalOptions& global, const OptimizeArgs& a, const CLI::App& cmd) {
#if FIRD_HAVE_MPI
    if (global.job && global.job->distributed())
        throw UsageError("--job-script writes a job: run it in one process, not under mpirun");
#endif
    if (a.out.empty())
        throw UsageError("--job-script needs --out DIR: the folder the job's search writes");
    if (!a.resume.empty())
        throw UsageError("--job-script cannot be given with --resume: the folder's run.sh or "
                         "slurm.sh continues its search");
    if (const auto why = cluster_shape_error(a.shape)) throw UsageError(*why);
    const Scene scene = load_scene(a.scene);
    refuse_start_outside_bounds(scene);
    refuse_unmeetable_constraints(scene, parameter_space(scene));
    // Refused here, not on the cluster an hour later.
    if (scene.target.kind == TargetDesc::Kind::None)
        throw std::runtime_error(
            fmt::format("{}: [target] is missing: a search needs a desired far field (a target "
                        "reflector or an IES / LDT file)",
                        scene.path));
    (void)requested_settings(scene, a, cmd);
    ClusterJob job{.dir = a.out, .scene = scene, .fird = this_program(), .shape = a.shape};
    const auto pass = [&](const char* option, const std::string& value) {
        if (!cmd.count(option)) return;
        job.optimize_options.push_back(option);
        job.optimize_options.push_back(value);
    };
    pass("--method", a.method);
    pass("--rays", a.rays);
    pass("--max-evals", std::to_string(a.max_evals));
    pass("--threshold", fmt::format("{}", a.threshold)); // shortest exact form
    pass("--seed", std::to_string(a.seed));
    if (a.refine) job.optimize_options.push_back("--refine");
    pass("--backend", a.backend);
    pass("--start", a.start);
    // fird's own options as given (0: not given): the ranks run as this command would.
    if (!global.device_name.empty())
        job.global_options.insert(job.global_options.end(), {"--device", global.device_name});
    if (global.validation) job.global_options.push_back("--validation");
    if (global.max_device_memory_mb > 0.0)
        job.global_options.insert(
            job.global_options.end(),
            {"--max-device-memory", fmt::format("{}", global.max_device_memory_mb)});
    if (global.max_batch_rays > 0)
        job.global_options.insert(job.global_options.end(),
                                  {"--max-batch-rays", std::to_string(global.max_batch_rays)});
    if (cmd.count("--rank-timeout")) // --resume takes it too
        job.launch_options = {"--rank-timeout", fmt::format("{}", a.rank_timeout)};
    const WrittenJob w = write_cluster_job(job);
    if (a.json)
        std::printf("%s\n", nlohmann::json{{"job",
                                            {{"dir", std::filesystem::path(w.scene).parent_path()},
                                             {"scene", w.scene},
                                             {"run_sh", w.run_sh},
                                             {"slurm_sh", w.slurm_sh},
                                             {"mpirun", w.mpirun},
                                             {"sbatch", w.sbatch}}}}
                                .dump(2)
                                .c_str());
    else
        std::printf("wrote %s, %s and %s\non this machine: %s\nunder Slurm: %s\nprogress: fird "
                    "follow %s\n",
                    w.scene.c_str(), w.run_sh.c_str(), w.slurm_sh.c_str(), w.mpirun.c_str(),
                    w.sbatch.c_str(),
                    shell_quoted(std::filesystem::path(w.scene).parent_path()).c_str());
    return 0;
}

int run_optimize(const GlobalOptions& global, const OptimizeArgs& a, const CLI::App& cmd) {
    if (cmd.count("--rank-timeout") && !(a.rank_timeout > 0.0))
        throw UsageError("--rank-timeout must be more than 0 s");
    for (const char* o : {"--ranks", "--nodes", "--gpus-per-node", "--time-limit", "--partition"})
        if (cmd.count(o) && !a.job_script)
            throw UsageError(fmt::format("{} goes with --job-script", o));
    if (a.job_script) return write_job(global, a, cmd);
#if FIRD_HAVE_MPI
    if (global.job && global.job->rank() > 0) return serve_search(global, a);
#endif
    const Scene scene = load_scene(a.scene);
    // No [reflector.optimize], or a press's limit nothing in the box meets: refused before
    // any work (the device is not even opened).
    refuse_start_outside_bounds(scene);
    refuse_unmeetable_constraints(scene, parameter_space(scene));
    SearchSettings settings = search_settings(scene);
    std::string out = a.out;
    SearchRequest request;
    nlohmann::json depends_on;
    if (!a.resume.empty()) {
        for (const char* o : {"--method", "--rays", "--max-evals", "--threshold", "--seed",
                              "--refine", "--backend", "--start"})
            if (cmd.count(o))
                throw UsageError(fmt::format(
                    "{} cannot be given with --resume: the search continues with the settings "
                    "it began with",
                    o));
        if (!out.empty() && std::filesystem::path(out) != std::filesystem::path(a.resume))
            throw UsageError("--out must be the --resume directory (or left out)");
        out = a.resume;
        Resumed resumed = resumed_settings(a.resume, scene);
        settings = resumed.settings;
        depends_on = std::move(resumed.depends_on);
        // The same start as it began from (a tailored one as recorded, not solved again).
        if (!resumed.start.is_null() && resumed.start.value("kind", "scene") == "tailored") {
            request.start_report = start_report_from_json(resumed.start);
            std::vector<double> x;
            for (const std::string& name : parameter_space(scene).names)
                x.push_back(request.start_report.parameters.at(name));
            request.start = x;
        }
        request.replay = read_history((std::filesystem::path(out) / "history.csv").string(),
                                      parameter_space(scene).names, scene.optimize);
    } else {
        settings = requested_settings(scene, a, cmd);
    }

    // A population method's module (pagmo) before the device, a trace or a file (a refined
    // search is refused as a usage error first, by run_search).
    if (searches_with_population(scene, settings) && !settings.refine) require_population_module();
    // And the exports' modules, for the folder's reflectors.pvd and the best part's CAD.
    if (!out.empty()) {
        (void)vtk_exports();
        (void)cad_exports();
    }
    const auto ctx = vk::Context::create(context_options(global));
    if (!a.resume.empty()) {
        check_device(a.resume, depends_on, ctx.summary());
        // The end of the run it continues is no longer the search's end: a follower
        // (fird follow, the workbench) must not read it as such.
        std::filesystem::remove(std::filesystem::path(out) / "search.json");
    }
    request.settings = settings;
    // The profile that makes the desired far field from the source's centre
    // (optimize/search_start.hpp).
    if (a.resume.empty() && a.start == "tailored") set_tailored_start(ctx, scene, request);
    std::unique_ptr<HistoryWriter> history;
    if (!out.empty()) {
        create_output_directory(out);
        const auto path = [&](const char* n) { return (std::filesystem::path(out) / n).string(); };
        if (a.resume.empty())
            write_text_file(path("options.json"),
                            settings_json(settings, scene, ctx.summary(), request).dump(2) + "\n");
        history = std::make_unique<HistoryWriter>(path("history.csv"), parameter_space(scene).names,
                                                  !a.resume.empty(), scene.optimize);
    }
    ProgressLine progress;
    const std::uint64_t grid = parameter_space(scene).lattice_size();
    std::uint64_t infeasible = 0;
    double best = HUGE_VAL;
    request.on_candidate = [&](const Candidate& c, const StageSummary& s) {
        if (history) history->write(c, s);
        infeasible += c.feasible ? 0 : 1;
        if (s.best) best = s.best_l2_lm;
        if (!progress.live()) return;
        const double elapsed = progress.elapsed_s();
        std::string eta;
        if (settings.method == SearchMethod::Grid && c.index + 1 < grid)
            eta =
                " | ETA " + clock_time(elapsed / double(c.index + 1) * double(grid - c.index - 1));
        progress.show(fmt::format(
            "optimize: {} evaluations ({} infeasible) | {} {:.0e} rays | best {} {:.5g} {} | {}{}",
            c.index + 1, infeasible, s.name, double(s.fidelity.rays),
            metric_name(scene.optimize.metric), best, metric_unit(scene.optimize.metric),
            clock_time(elapsed), eta));
    };
    SearchControl control;
    request.control = &control;
#if FIRD_HAVE_MPI
    // Under mpirun: the batches' shares go to the other ranks (the history is rank 0's).
    std::optional<distributed::Farm> farm;
    if (global.job && global.job->distributed()) {
        // The history is flushed per candidate: the search continues from it on any number
        // of ranks.
        const std::string after_loss =
            out.empty() ? std::string()
                        : fmt::format("; {}/history.csv keeps the candidates so far: fird "
                                      "optimize {} --resume {} continues",
                                      out, a.scene, out);
        farm.emplace(*global.job, &control,
                     cmd.count("--rank-timeout") ? std::optional(a.rank_timeout) : std::nullopt,
                     after_loss);
        request.settings.distributed = distributed::search_tracing(*farm, settings.backend);
    }
#endif
    SearchOutcome outcome;
    const auto search = [&] {
        const InterruptScope interrupts(control);
        outcome = run_search(ctx, scene, request);
        return outcome.result.time_s;
    };
#if FIRD_HAVE_MPI
    if (const auto code = run_shared(farm, control, "candidates", search)) return *code;
#else
    search();
#endif
    progress.finish();
    const SearchResult& r = outcome.result;
    for (const FlatDirection& d : r.flat_directions)
        std::fprintf(stderr, "fird: note: %s: %s\n", scene.path.c_str(), describe(d).c_str());
    if (!out.empty()) {
        write_search_outputs(out, scene, outcome);
        (void)vtk_exports().search_reflectors(scene, r, out); // reflectors.pvd for ParaView
        write_best_part(out, scene, r);
    }
    if (ctx.validation_errors() > 0)
        throw std::runtime_error("Vulkan validation errors were reported (see above)");
    if (a.json) {
        std::printf("%s\n", search_json(r).dump(2).c_str());
    } else {
        std::printf("%s: %s search, %zu evaluations (%llu infeasible), stopped: %s, %.1f s\n",
                    scene.name.c_str(), r.method.c_str(), r.history.size(),
                    static_cast<unsigned long long>(r.infeasible), stop_reason_name(r.stopped),
                    r.time_s);
        if (r.start.kind == "tailored")
            std::printf(
                "%s",
                fmt::format("start: tailored ({} edge rays, the rim {:.1f} deg from "
                            "the nadir holding {:.1f} % of the source's flux{}); "
                            "{} at start {}\n",
                            r.start.edge_ray, r.start.rim_polar_deg, 100.0 * r.start.source_share,
                            r.start.clamped.empty() ? ""
                                                    : fmt::format(", {} heights clamped into their "
                                                                  "bounds",
                                                                  r.start.clamped.size()),
                            r.metric,
                            r.start_l2_lm ? fmt::format("{:.6g} {}", *r.start_l2_lm, r.metric_unit)
                                          : std::string("not traced"))
                    .c_str());
        if (r.best) {
            std::string params;
            for (const auto& [k, v] : r.best_parameters)
                params += fmt::format(" {}={:.6g}", k, v);
            std::printf("%s", fmt::format("best:{} ({} {:.6g} {} at evaluation {})\n", params,
                                          r.metric, r.best_l2_lm, r.metric_unit, *r.best)
                                  .c_str());
        }
        if (r.smoothness_weight > 0.0 && r.best_bending_energy)
            std::printf("%s",
                        fmt::format("smoothness: bending energy {:.6g} (start {:.6g}), "
                                    "penalty {:.6g} {} at weight {:g}\n",
                                    *r.best_bending_energy, r.start_bending_energy.value_or(0.0),
                                    r.smoothness_weight * *r.best_bending_energy, r.metric_unit,
                                    r.smoothness_weight)
                            .c_str());
        for (const ConstraintAtOptimum& c : r.constraints)
            std::printf("%s",
                        fmt::format("constraint {}: {:.4g} against {:g}, {}{}\n", c.name, c.value,
                                    c.limit, c.met ? "met" : "BROKEN",
                                    c.active ? " and active (" + c.active_by + " breaks it)" : "")
                            .c_str());
        if (r.population)
            std::printf("%s", fmt::format("population: {}; {}\n", population_summary(*r.population),
                                          r.population->verdict)
                                  .c_str());
        if (r.levenberg)
            std::printf("%s", fmt::format("polish: {}\n", levenberg_summary(*r.levenberg)).c_str());
        if (r.lattice) std::printf("lattice: %s\n", r.lattice->verdict.c_str());
        if (r.refine) std::printf("refine: %s\n", r.refine->verdict.c_str());
        if (r.final_l2_lm && r.noise_floor_l2_lm)
            std::printf("%s",
                        fmt::format("final {} {:.6g} {} with fresh rays; noise floor {:.6g} "
                                    "{} (ratio {:.3f})\n",
                                    r.metric, *r.final_l2_lm, r.metric_unit, *r.noise_floor_l2_lm,
                                    r.metric_unit, *r.final_l2_lm / *r.noise_floor_l2_lm)
                            .c_str());
        if (r.photometrics)
            std::printf("best: %s\n",
                        photometrics_text(photometrics_json(*r.photometrics)).c_str());
        if (r.desired_photometrics)
            std::printf("desired: %s\n",
                        photometrics_text(photometrics_json(*r.desired_photometrics)).c_str());
        if (!out.empty()) std::printf("wrote %s/\n", out.c_str());
    }
    return r.stopped == StopReason::Interrupted ? 130 : 0;
}

} // namespace

void register_optimize(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("optimize",
                                   "Search the reflector's parameters for the desired far field");
    auto a = std::make_shared<OptimizeArgs>();
    cmd->add_option("SCENE", a->scene, "Scene file (TOML) with [reflector.optimize] and [target]")
        ->required();
    cmd->add_option(
           "--method", a->method,
           "auto (default), grid, bobyqa, sbplx, cobyla, direct, crs2, cmaes, xnes, levenberg")
        ->check(CLI::IsMember(method_names()));
    cmd->add_option("--rays", a->rays,
                    "Rays per evaluation, one count per stage (auto), e.g. 1e5,1e6,1e7");
    cmd->add_option("--max-evals", a->max_evals, "Most candidates to consider")
        ->check(CLI::Range(1.0, 1e8));
    cmd->add_option("--threshold", a->threshold,
                    "Stop once l2 falls below this (lm; cd with [optimize] metric = candela_l2)");
    cmd->add_option("--seed", a->seed, "Seed of the search's rays")->check(CLI::NonNegativeNumber);
    cmd->add_flag("--refine", a->refine,
                  "After the lattice (auto, grid), BOBYQA within one step of its best point");
    cmd->add_option("--backend", a->backend,
                    "gpu (the fast path, default) or cpu (every candidate by the exact CPU "
                    "reference: a search judged by another tracer, far slower)")
        ->check(CLI::IsMember({"gpu", "cpu"}));
    cmd->add_option("--start", a->start,
                    "scene (default: the scene's reflector) or tailored (the profile family: "
                    "the profile a point source at the source's centre needs for the desired far "
                    "field, by flux mapping)")
        ->check(CLI::IsMember({"scene", "tailored"}));
    cmd->add_flag("--json", a->json, "Print one JSON object");
    cmd->add_option("--out", a->out,
                    "Write history.csv, progress.png, best.toml, the best far field, and the best "
                    "reflector as reflector.step / .stl with manufacturability.json / .png here");
    cmd->add_option("--resume", a->resume, "Continue the search recorded in this --out directory");
    cmd->add_flag("--job-script", a->job_script,
                  "Do not search: write the --out folder's scene.toml, run.sh (mpirun on this "
                  "machine) and slurm.sh (sbatch) that run this search there, with these options "
                  "(docs/scale-out.md)");
    cmd->add_option("--ranks", a->shape.ranks, "--job-script: run.sh's ranks (default 4)");
    cmd->add_option("--nodes", a->shape.nodes, "--job-script: slurm.sh's nodes (default 1)");
    cmd->add_option("--gpus-per-node", a->shape.gpus_per_node,
                    "--job-script: slurm.sh's GPUs per node, one rank each (default 4)");
    cmd->add_option("--time-limit", a->shape.time_limit,
                    "--job-script: slurm.sh's time limit (default 04:00:00)");
    cmd->add_option("--partition", a->shape.partition,
                    "--job-script: slurm.sh's partition (default: the cluster's)");
    cmd->add_option("--rank-timeout", a->rank_timeout,
                    "Under mpirun or srun: the longest wait (s) on a rank for its share of a "
                    "batch before the search ends naming it (default: 60 s plus ten times rank "
                    "0's own share)");
    cmd->callback([&global, &run, a, cmd] {
        run = [&global, a, cmd] { return run_optimize(global, *a, *cmd); };
    });
}

} // namespace fird::app
