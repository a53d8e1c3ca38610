#include "evaluation.hpp"

#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/npy.hpp"
#include "model/energy_balance.hpp"
#include "photometry/beam_metrics.hpp"
#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_pictures.hpp"
#include "photometry/photometry_file.hpp"
#include "plot/farfield_picture.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

Scene apply_overrides(Scene scene, const TraceOverrides& o) {
    if (o.rays) {
        if (*o.rays == 0) throw std::invalid_argument("--rays must be at least 1");
        scene.trace.rays = *o.rays;
    }
    if (o.seed) {
        scene.trace.seed = *o.seed;
        if (scene.target.kind == TargetDesc::Kind::Reflector && scene.target.seed == *o.seed)
            scene.target.seed = *o.seed + 1; // stay independent of the reflector's run
    }
    if (o.sampler) scene.trace.sampler = *o.sampler;
    return scene;
}

ReferenceOptions reference_options(const Scene& scene, unsigned threads) {
    const TraceSettings& t = scene.trace;
    return {.rays = t.rays,
            .seed = t.seed,
            .sampler = t.sampler,
            .max_bounces = t.max_bounces,
            .bounce_policy = t.bounce_policy,
            .farfield_w = t.farfield_w,
            .farfield_h = t.farfield_h,
            .threads = threads,
            .material = scene.reflector.material,
            .direct = t.direct};
}

Evaluation evaluate_reference(const Scene& scene, unsigned threads) {
    const auto t0 = std::chrono::steady_clock::now();
    ReferenceOptions options = reference_options(scene, threads);
    const Surface surface = Surface::make(scene.reflector, scene.holder);
    ReferenceResult result = trace_reference(scene.source, surface, options);

    Evaluation e;
    e.backend = "cpu";
    e.device = fmt::format("cpu reference (double precision, {} threads)", result.threads);
    e.tally = result.tally;
    e.energy_per_ray_lm = result.energy_per_ray_lm;
    e.farfield = std::move(result.farfield);
    e.timings.trace_ms = result.trace_ms; // the rayset is sampled inside the trace loop

    if (scene.target.kind == TargetDesc::Kind::Reflector) {
        const Surface target = Surface::make(target_reflector(scene), scene.holder);
        options.seed = scene.target.seed;
        e.target_farfield = trace_reference(scene.source, target, options).farfield;
    } else if (scene.target.kind == TargetDesc::Kind::Photometric) {
        e.target_farfield = photometric_target(scene, e.farfield.total_lm());
    }
    if (e.target_farfield) {
        const auto tc = std::chrono::steady_clock::now();
        e.l2_lm = farfield_distance(e.farfield, *e.target_farfield, scene.optimize.metric);
        e.metric = scene.optimize.metric;
        e.timings.compare_ms = ms_since(tc);
    }
    e.timings.total_ms = ms_since(t0);
    return e;
}

FarField photometric_target(const Scene& scene, double reflector_farfield_lm) {
    CandelaTable table;
    try {
        table = read_photometry(scene.target.resolved_path);
    } catch (const std::exception& ex) {
        throw std::invalid_argument(fmt::format("{}: [target] file: {}", scene.path, ex.what()));
    }
    FarField ff = farfield_from_table(table, scene.trace.farfield_w, scene.trace.farfield_h);
    const double total = ff.total_lm();
    if (!scene.target.absolute) {
        if (!(total > 0.0))
            throw std::invalid_argument(fmt::format("{}: [target] file: {} emits no light to scale",
                                                    scene.path, table.path));
        for (double& v : ff.lm)
            v *= reflector_farfield_lm / total;
    }
    return ff;
}

nlohmann::json profile_json(const std::vector<BounceProfile>& bounces) {
    nlohmann::json rows = nlohmann::json::array();
    for (std::size_t b = 0; b < bounces.size(); ++b) {
        const BounceProfile& p = bounces[b];
        const double rays = double(std::max<std::uint64_t>(p.rays, 1));
        rows.push_back(
            {{"bounce", b},
             {"rays", p.rays},
             {"trace_ms", p.trace_ms},
             {"order_ms", p.order_ms},
             {"ns_per_ray", p.trace_ms * 1e6 / rays},
             {"steps_per_ray", double(p.steps) / rays},
             {"leaf_tests_per_ray", double(p.leaf_tests) / rays},
             {"lane_utilization", p.lane_steps ? double(p.steps) / double(p.lane_steps) : 0.0},
             {"leaf_lane_utilization",
              p.lane_leaf_tests ? double(p.leaf_tests) / double(p.lane_leaf_tests) : 0.0}});
    }
    return rows;
}

std::string profile_table(const std::vector<BounceProfile>& bounces) {
    std::string out = "| bounce | rays | trace ms | order ms | ns per ray | steps per ray | leaf "
                      "tests per ray | lane utilization | leaf lane utilization |\n"
                      "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& row : profile_json(bounces))
        out += fmt::format(
            "| {} | {} | {:.1f} | {:.1f} | {:.0f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} |\n",
            row["bounce"].get<std::size_t>(), row["rays"].get<std::uint64_t>(),
            row["trace_ms"].get<double>(), row["order_ms"].get<double>(),
            row["ns_per_ray"].get<double>(), row["steps_per_ray"].get<double>(),
            row["leaf_tests_per_ray"].get<double>(), row["lane_utilization"].get<double>(),
            row["leaf_lane_utilization"].get<double>());
    return out;
}

nlohmann::json evaluation_json(const Evaluation& e) {
    const RayTally& t = e.tally;
    const EnergyBalance energy = energy_balance(t, e.energy_per_ray_lm);
    nlohmann::json j = {{"backend", e.backend},
                        {"device", e.device},
                        {"rays_emitted", t.emitted},
                        {"rays_effective", t.emitted - t.discarded},
                        {"rays_reflected", t.farfield},
                        {"rays_direct", t.direct},
                        {"rays_discarded", t.discarded},
                        {"rays_lost", t.lost},
                        {"rays_aborted", e.rays_aborted},
                        {"rays_by_reflections", t.by_reflections},
                        {"energy_emitted_lm", energy.emitted_lm},
                        {"energy_farfield_lm", energy.farfield_lm},
                        {"energy_direct_lm", energy.direct_lm},
                        {"energy_discarded_lm", energy.discarded_lm},
                        {"energy_lost_lm", energy.lost_lm},
                        {"energy_absorbed_lm", energy.absorbed_lm},
                        {"energy_binned_lm", energy.binned_lm},
                        {"timings_ms",
                         {{"rayset", e.timings.rayset_ms},
                          {"heightfield", e.timings.heightfield_ms},
                          {"trace", e.timings.trace_ms},
                          {"histogram", e.timings.histogram_ms},
                          {"compare", e.timings.compare_ms},
                          {"total", e.timings.total_ms}}}};
    if (e.l2_lm) {
        j["l2"] = *e.l2_lm;
        j["metric"] = metric_name(e.metric);
        j["metric_unit"] = metric_unit(e.metric);
    }
    if (!e.farfield.lm.empty())
        j["photometrics"] = photometrics_json(photometrics(e.farfield, energy.emitted_lm));
    if (e.target_farfield)
        j["desired_photometrics"] =
            photometrics_json(photometrics(*e.target_farfield, energy.emitted_lm));
    if (!e.bounces.empty()) j["profile"] = profile_json(e.bounces);
    if (e.submissions) j["submissions"] = *e.submissions;
    if (e.device_memory_allocations) j["device_memory_allocations"] = *e.device_memory_allocations;
    return j;
}

void write_evaluation_outputs(const std::string& dir, const Scene& scene, const Evaluation& e,
                              const std::string& producer, double plane_distance_m) {
    namespace fs = std::filesystem;
    create_output_directory(dir);
    const auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
    const FarField& f = e.farfield;
    write_npy_f32(path("farfield.npy"), f.lm, f.height, f.width);
    plot::write_farfield_png(path("farfield.png"), f, {.title = scene.name + ": far field"});
    // The far field as luminaire files (5 deg C planes, 1 deg gamma) for photometric
    // tools, when it holds light and its cells are no coarser than that grid.
    if (f.total_lm() > 0.0 && f.width >= 72 && f.height >= 180) {
        const CandelaTable table = table_from_farfield(f, 5.0, 1.0);
        const PhotometryLabels labels{
            .luminaire = scene.name,
            .test = fmt::format("{}, {} backend, {} rays", producer, e.backend, e.tally.emitted),
            .other = scene.path,
            .lamp_flux_lm = scene.source.flux_lm,
            .simulated = true};
        write_photometry(path("farfield.ies"), table, labels);
        write_photometry(path("farfield.ldt"), table, labels);
    }
    // What a lighting engineer reads: the polar map, isocandela lines and the illuminance
    // on a plane, beside the desired ones (photometry/luminaire_pictures.hpp).
    if (f.total_lm() > 0.0)
        write_luminaire_views(dir, f,
                              e.target_farfield && e.target_farfield->total_lm() > 0.0
                                  ? &*e.target_farfield
                                  : nullptr,
                              {.title = scene.name, .plane_distance_m = plane_distance_m});
    if (e.target_farfield) {
        const FarField& t = *e.target_farfield;
        write_npy_f32(path("target.npy"), t.lm, t.height, t.width);
        plot::write_farfield_png(path("target.png"), t,
                                 {.title = scene.name + ": desired far field"});
        FarField diff = f;
        for (std::size_t i = 0; i < diff.lm.size(); ++i)
            diff.lm[i] -= t.lm[i];
        plot::write_farfield_png(path("difference.png"), diff,
                                 {.title = fmt::format("{}: obtained - desired, l2 = {:.4g} lm",
                                                       scene.name, e.l2_lm.value_or(0.0)),
                                  .signed_values = true});
    }
}

} // namespace fird
