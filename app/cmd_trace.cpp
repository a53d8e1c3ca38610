// fird trace SCENE: one lighting evaluation (DESIGN.md §5).
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "evaluation/evaluation.hpp"
#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "parse.hpp"
#include "photometry/beam_metrics.hpp"
#include "vk/context.hpp"

namespace fird::app {

void register_trace(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("trace", "One lighting evaluation of a scene");
    struct Args {
        std::string scene;
        std::string backend = "gpu";
        std::string sampler;
        std::string out;
        std::string rays;
        std::uint64_t seed = 0;
        unsigned threads = 0;
        double plane_distance_m = 3.0;
        bool json = false;
        bool profile = false;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("SCENE", a->scene, "Scene file (TOML)")->required();
    cmd->add_option("--rays", a->rays, "Rays to emit (overrides [trace] rays; 1e6 style allowed)");
    cmd->add_option("--seed", a->seed, "Seed (overrides [trace] seed)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--backend", a->backend, "gpu (the fast path) or cpu (the exact reference)")
        ->check(CLI::IsMember({"gpu", "cpu"}));
    cmd->add_option("--sampler", a->sampler,
                    "stratified, random (independent rays) or sobol (overrides [trace] sampler)")
        ->check(CLI::IsMember(sampler_names()));
    cmd->add_option("--threads", a->threads, "CPU threads for the reference (0: all)")
        ->check(CLI::Range(0.0, 4096.0));
    cmd->add_flag("--json", a->json, "Print one JSON object");
    cmd->add_flag("--profile", a->profile,
                  "Fast path: per bounce, rays, device times, walk steps and leaf tests per ray "
                  "and the SIMD lane utilization (a counting variant of the trace pass)");
    cmd->add_option("--out", a->out, "Write farfield.npy and images to this directory");
    cmd->add_option("--plane-distance", a->plane_distance_m,
                    "Metres from the luminaire to the plane of --out's illuminance.png (default 3)")
        ->check(finite_range(1e-3, 1e4));
    cmd->callback([&global, &run, a, cmd] {
        run = [&global, a, cmd] {
            TraceOverrides o;
            if (cmd->count("--rays")) o.rays = parse_count("--rays", a->rays, 1e10);
            if (cmd->count("--seed")) o.seed = a->seed;
            if (!a->sampler.empty()) o.sampler = *sampler_from_name(a->sampler);
            const Scene scene = apply_overrides(load_scene(a->scene), o);
            Evaluation e;
            if (a->backend == "gpu") {
                const auto ctx = vk::Context::create(context_options(global));
                e = evaluate_fast(ctx, scene, {.profile = a->profile, .read_farfields = true});
                if (ctx.validation_errors() > 0)
                    throw std::runtime_error("Vulkan validation errors were reported (see above)");
            } else {
                if (a->profile)
                    throw UsageError("--profile: the cpu backend has no trace passes to profile");
                e = evaluate_reference(scene, a->threads);
            }
            if (e.tally.below_surface > 0)
                std::fprintf(stderr,
                             "fird: warning: %s: %llu rays start below the reflector surface "
                             "(counted as lost): the reflector cuts the light source\n",
                             scene.path.c_str(),
                             static_cast<unsigned long long>(e.tally.below_surface));
            if (!a->out.empty())
                write_evaluation_outputs(a->out, scene, e, "fird trace", a->plane_distance_m);
            const auto j = evaluation_json(e);
            if (a->json) {
                std::printf("%s\n", j.dump(2).c_str());
            } else {
                std::printf("%s", fmt::format("{}: {} rays emitted, {} effective, {} reflected to "
                                              "the far field ({:.2f} lm of {:.2f} lm)\n",
                                              scene.name, e.tally.emitted,
                                              e.tally.emitted - e.tally.discarded, e.tally.farfield,
                                              j["energy_farfield_lm"].get<double>(),
                                              j["energy_emitted_lm"].get<double>())
                                      .c_str());
                if (e.l2_lm)
                    std::printf("%s to the target: %.6g %s\n", metric_name(e.metric), *e.l2_lm,
                                metric_unit(e.metric));
                std::printf("%s\n", photometrics_text(j["photometrics"]).c_str());
                std::printf("time: %.1f ms on %s\n", e.timings.total_ms, e.device.c_str());
                if (!e.bounces.empty()) std::printf("%s", profile_table(e.bounces).c_str());
                if (!a->out.empty())
                    std::printf("wrote %s/farfield.npy and %s/farfield.png\n", a->out.c_str(),
                                a->out.c_str());
            }
            return 0;
        };
    });
}

} // namespace fird::app
