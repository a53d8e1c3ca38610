#include "tolerance.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <numbers>

#include <unistd.h>

#include <fmt/format.h>

#include "calibrate/order_statistics.hpp"
#include "evaluation/desired_farfield.hpp"
#include "io/atomic_file.hpp"
#include "model/design_parameters.hpp"
#include "model/source.hpp"
#include "model/tolerance_check.hpp"
#include "optimize/parameter_space.hpp"
#include "photometry/beam_metrics.hpp"
#include "plot/chart.hpp"
#include "sampling/philox.hpp"
#include "tolerance/surface_error.hpp"

namespace fird {

namespace {

// Streams of the draws (the counter's third word; the surface error's from 20100 on).
constexpr std::uint32_t kShiftStream = 20000, kShiftZStream = 20001, kTiltStream = 20002,
                        kReflectanceStream = 20003;

// Two independent standard normals from one Philox block.
std::pair<double, double> normals(std::uint64_t seed, std::uint64_t realisation,
                                  std::uint32_t stream) {
    const auto u = philox_uniforms(seed, realisation, stream);
    return standard_normals(u[0], u[1]);
}

// The scene as realisation `d` makes it (the surface error's mesh written to `mesh_path`
// where the surface tolerance is given: then every run, the nominal one too, traces a mesh
// of the same grid, so that the runs differ by their errors, not by the mesh's sampling).
Scene perturbed_scene(const Scene& base, const ToleranceDesc& tol, const ToleranceDraw& d,
                      std::uint64_t seed, std::uint64_t realisation, const std::string& mesh_path,
                      double& surface_rms_mm) {
    Scene s = base;
    std::map<std::string, double> moved{{"x_mm", base.source.center_mm.x + d.source_shift_mm.x},
                                        {"y_mm", base.source.center_mm.y + d.source_shift_mm.y},
                                        {"z_mm", base.source.center_mm.z + d.source_shift_mm.z}};
    if (source_has_axis(base.source)) {
        moved["tilt_x_deg"] = d.tilt_x_deg;
        moved["tilt_y_deg"] = d.tilt_y_deg;
    }
    s.source = moved_source(base.source, moved);
    s.reflector.material.reflectance = d.reflectance;
    surface_rms_mm = 0.0;
    if (tol.surface_rms_mm > 0.0) {
        const SurfaceError error =
            d.surface ? draw_surface_error(tol.surface_rms_mm, tol.surface_correlation_mm, seed,
                                           realisation)
                      : SurfaceError{};
        const PerturbedMesh mesh = perturbed_mesh(s, error, tol.surface_correlation_mm, mesh_path);
        s.reflector = mesh.reflector;
        surface_rms_mm = mesh.rms_mm;
    }
    return s;
}

// A kind with no rows (a run stopped before it, or every one of its realisations
// infeasible) has no spread: null, never zeros that read as measured.
nlohmann::json spread_json(const std::vector<double>& values) {
    if (values.empty()) return nullptr;
    const Spread s = spread_of(values);
    return {{"median", s.median}, {"p5", s.p5}, {"p95", s.p95}};
}

// The rows of one kind, and one metric of theirs.
std::vector<double> metric(const std::vector<RealisationResult>& rows, const std::string& kind,
                           double (*get)(const RealisationResult&)) {
    std::vector<double> v;
    for (const RealisationResult& r : rows)
        if (r.kind == kind && r.feasible) v.push_back(get(r));
    return v;
}

double get_l2(const RealisationResult& r) {
    return r.l2_lm.value_or(0.0);
}
double get_efficiency(const RealisationResult& r) {
    return r.efficiency;
}
double get_peak(const RealisationResult& r) {
    return r.peak_cd;
}
double get_beam(const RealisationResult& r) {
    return r.beam_angle_deg;
}

nlohmann::json metrics_json(const std::vector<RealisationResult>& rows, const std::string& kind,
                            bool l2) {
    nlohmann::json j = {{"efficiency", spread_json(metric(rows, kind, get_efficiency))},
                        {"peak_cd", spread_json(metric(rows, kind, get_peak))},
                        {"beam_angle_deg", spread_json(metric(rows, kind, get_beam))}};
    if (l2) j["l2"] = spread_json(metric(rows, kind, get_l2));
    return j;
}

} // namespace

std::vector<std::string> active_tolerances(const ToleranceDesc& t) {
    std::vector<std::string> a;
    if (t.source_shift_mm != glm::dvec3(0.0)) a.push_back("source_shift");
    if (t.source_tilt_deg > 0.0) a.push_back("source_tilt");
    if (t.surface_rms_mm > 0.0) a.push_back("surface");
    if (t.reflectance_sd > 0.0) a.push_back("reflectance");
    return a;
}

ToleranceDraw draw_tolerances(const ToleranceDesc& t, const Scene& scene, std::uint64_t seed,
                              std::uint64_t r, const std::string& only) {
    ToleranceDraw d;
    d.reflectance = scene.reflector.material.reflectance;
    const auto on = [&](const char* name) { return only.empty() || only == name; };
    if (on("source_shift")) {
        const auto [x, y] = normals(seed, r, kShiftStream);
        const auto [z, unused] = normals(seed, r, kShiftZStream);
        (void)unused;
        d.source_shift_mm = glm::dvec3(x, y, z) * t.source_shift_mm;
    }
    if (on("source_tilt")) {
        const auto [a, b] = normals(seed, r, kTiltStream);
        d.tilt_x_deg = a * t.source_tilt_deg;
        d.tilt_y_deg = b * t.source_tilt_deg;
    }
    if (on("reflectance") && t.reflectance_sd > 0.0)
        d.reflectance = std::clamp(d.reflectance + normals(seed, r, kReflectanceStream).first *
                                                       t.reflectance_sd,
                                   0.0, 1.0);
    d.surface = on("surface") && t.surface_rms_mm > 0.0;
    return d;
}

Spread spread_of(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return {sorted_quantile(v, 0.5), sorted_quantile(v, 0.05), sorted_quantile(v, 0.95)};
}

namespace {

// The perturbed mesh's file: one per process (ranks on a node share the scratch folder),
// removed when the realisations are traced.
struct ScratchMesh {
    std::string path;
    explicit ScratchMesh(const std::string& dir)
        : path((std::filesystem::path(dir.empty() ? std::filesystem::temp_directory_path().string()
                                                  : dir) /
                fmt::format("fird_tolerance_{}.obj", ::getpid()))
                   .string()) {}
    ~ScratchMesh() {
        std::error_code ec;
        std::filesystem::remove(path, ec);
    }
    ScratchMesh(const ScratchMesh&) = delete;
    ScratchMesh& operator=(const ScratchMesh&) = delete;
};

// One realisation traced as an independent evaluation; its far field into `farfield` if given.
RealisationResult trace_realisation(const vk::Context& ctx, const Scene& scene,
                                    const ToleranceRun& run, const std::string& kind,
                                    std::uint64_t r, const ToleranceDraw& d,
                                    const FarField* desired, const std::string& mesh_path,
                                    FarField* farfield = nullptr) {
    RealisationResult row{.kind = kind, .realisation = r, .draw = d};
    const Scene s =
        perturbed_scene(scene, run.tolerances, d, run.seed, r, mesh_path, row.surface_rms_mm);
    row.feasible = candidate_feasibility(s, s.reflector).feasible;
    Evaluator ev(ctx, s, scene_fidelity(s), run.backend);
    if (desired) ev.set_desired(*desired);
    const CandidateResult result = ev.evaluate(s.reflector);
    row.l2_lm = result.l2_lm;
    row.efficiency = result.farfield_lm / s.source.flux_lm;
    FarField traced = ev.farfield();
    const BeamMetrics beam = beam_metrics(traced);
    row.peak_cd = beam.peak_cd;
    row.beam_angle_deg = beam.beam_angle_deg;
    if (farfield) *farfield = std::move(traced);
    return row;
}

} // namespace

std::vector<RealisationResult> trace_realisations(const vk::Context& ctx, const Scene& scene,
                                                  const ToleranceRun& run,
                                                  std::span<const RealisationKey> keys,
                                                  const FarField* desired) {
    const ScratchMesh mesh(run.scratch_dir);
    std::vector<RealisationResult> rows;
    for (const RealisationKey& k : keys) {
        const ToleranceDraw d =
            k.kind == "joint"
                ? draw_tolerances(run.tolerances, scene, run.seed, k.realisation)
                : draw_tolerances(run.tolerances, scene, run.seed, k.realisation, k.kind);
        rows.push_back(
            trace_realisation(ctx, scene, run, k.kind, k.realisation, d, desired, mesh.path));
    }
    return rows;
}

ToleranceResult run_tolerance(const vk::Context& ctx, const Scene& scene, const ToleranceRun& run) {
    const auto t0 = std::chrono::steady_clock::now();
    const ToleranceDesc& tol = run.tolerances;
    if (const auto problem = tolerance_problem(tol, scene.source))
        throw std::invalid_argument(problem->key + ": " + problem->reason);
    ToleranceResult out;
    out.tolerances = tol;
    out.seed = run.seed;
    out.active = active_tolerances(tol);

    std::optional<FarField> desired;
    const std::size_t total = 1 + tol.realisations * (1 + out.active.size());
    std::size_t done = 0;
    // The nominal luminaire (traced as every realisation is), then the desired far field:
    // the scene's own target (a reflector traced as written, or a luminaire file scaled to
    // the nominal luminaire's flux).
    FarField nominal_farfield;
    {
        const ScratchMesh mesh(run.scratch_dir);
        out.nominal = trace_realisation(ctx, scene, run, "nominal", 0,
                                        draw_tolerances(ToleranceDesc{}, scene, run.seed, 0),
                                        nullptr, mesh.path, &nominal_farfield);
    }
    if (run.progress) run.progress(out.nominal, ++done, total);
    if (scene.target.kind != TargetDesc::Kind::None) {
        desired =
            desired_farfield(ctx, scene, out.nominal.efficiency * scene.source.flux_lm, run.backend)
                .farfield;
        out.nominal.l2_lm = farfield_distance(nominal_farfield, *desired, scene.optimize.metric);
    }
    std::vector<RealisationKey> keys;
    for (std::uint64_t r = 0; r < tol.realisations; ++r)
        keys.push_back({"joint", r});
    for (const std::string& name : out.active)
        for (std::uint64_t r = 0; r < tol.realisations; ++r)
            keys.push_back({name, r});
    const FarField* compared = desired ? &*desired : nullptr;
    const RealisationTracer here = [&](std::span<const RealisationKey> ks) {
        return trace_realisations(ctx, scene, run, ks, compared);
    };
    // One at a time here; across processes a few for each per exchange (the progress
    // follows each exchange).
    const std::size_t chunk = run.distributed.trace ? 4 * run.distributed.processes : 1;
    for (std::size_t first = 0; first < keys.size(); first += chunk) {
        if (run.stop && run.stop->load()) {
            out.stopped = true;
            break;
        }
        const auto part = std::span(keys).subspan(first, std::min(chunk, keys.size() - first));
        for (RealisationResult& row :
             run.distributed.trace ? run.distributed.trace(part, compared, here) : here(part)) {
            out.rows.push_back(std::move(row));
            if (run.progress) run.progress(out.rows.back(), ++done, total);
        }
    }
    out.ranked_by = desired ? "l2" : "efficiency";
    out.metric = scene.optimize.metric;
    for (const RealisationResult& row : out.rows)
        out.infeasible += row.feasible ? 0 : 1;
    // Ranked among the tolerances that have feasible rows, and only when each has: a run
    // stopped before some tolerance's own runs names none.
    double widest = -1.0;
    for (const std::string& name : out.active) {
        const std::vector<double> v = metric(out.rows, name, desired ? get_l2 : get_efficiency);
        if (v.empty()) {
            out.most_sensitive.clear();
            break;
        }
        const Spread s = spread_of(v);
        if (s.p95 - s.p5 > widest) {
            widest = s.p95 - s.p5;
            out.most_sensitive = name;
        }
    }
    out.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

nlohmann::json tolerance_json(const ToleranceResult& r) {
    const bool l2 = r.ranked_by == "l2";
    const ToleranceDesc& t = r.tolerances;
    nlohmann::json j = metrics_json(r.rows, "joint", l2);
    j["realisations"] = t.realisations;
    j["seed"] = r.seed;
    j["tolerances"] = {
        {"source_shift_mm", {t.source_shift_mm.x, t.source_shift_mm.y, t.source_shift_mm.z}},
        {"source_tilt_deg", t.source_tilt_deg},
        {"surface_rms_mm", t.surface_rms_mm},
        {"surface_correlation_mm", t.surface_correlation_mm},
        {"reflectance_sd", t.reflectance_sd}};
    nlohmann::json nominal = {{"efficiency", r.nominal.efficiency},
                              {"peak_cd", r.nominal.peak_cd},
                              {"beam_angle_deg", r.nominal.beam_angle_deg}};
    if (r.nominal.l2_lm) nominal["l2"] = *r.nominal.l2_lm;
    j["nominal"] = nominal;
    nlohmann::json sens = nlohmann::json::array();
    for (const std::string& name : r.active) {
        nlohmann::json s = metrics_json(r.rows, name, l2);
        s["tolerance"] = name;
        sens.push_back(s);
    }
    j["sensitivities"] = sens;
    j["most_sensitive"] =
        r.most_sensitive.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.most_sensitive);
    j["ranked_by"] = r.ranked_by;
    j["metric"] = metric_name(r.metric);
    j["metric_unit"] = metric_unit(r.metric);
    j["infeasible"] = r.infeasible;
    j["stopped"] = r.stopped;
    j["time_s"] = r.time_s;
    return j;
}

void write_tolerance_outputs(const std::string& dir, const Scene& scene, const ToleranceResult& r) {
    namespace fs = std::filesystem;
    create_output_directory(dir);
    const auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
    // The metric's column is named as in history.csv: l2_lm, or candela_l2_cd.
    std::string csv =
        fmt::format("kind,realisation,source_dx_mm,source_dy_mm,source_dz_mm,tilt_x_deg,tilt_y_deg,"
                    "reflectance,surface_rms_mm,{}_{},efficiency,peak_cd,beam_angle_deg,feasible\n",
                    metric_name(r.metric), metric_unit(r.metric));
    std::vector<RealisationResult> all{r.nominal};
    all.insert(all.end(), r.rows.begin(), r.rows.end());
    for (const RealisationResult& row : all) {
        const ToleranceDraw& d = row.draw;
        csv += fmt::format("{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},{:.9g},"
                           "{:.9g},{:.9g},{}\n",
                           row.kind, row.realisation, d.source_shift_mm.x, d.source_shift_mm.y,
                           d.source_shift_mm.z, d.tilt_x_deg, d.tilt_y_deg, d.reflectance,
                           row.surface_rms_mm,
                           row.l2_lm ? fmt::format("{:.9g}", *row.l2_lm) : std::string(),
                           row.efficiency, row.peak_cd, row.beam_angle_deg, row.feasible ? 1 : 0);
    }
    write_text_file(path("tolerance.csv"), csv);
    write_text_file(path("tolerance.json"), tolerance_json(r).dump(2) + "\n");
    plot::write_chart_png(path("tolerance.png"), tolerance_chart(scene.name, r));
}

plot::Chart tolerance_chart(const std::string& scene_name, const ToleranceResult& r) {
    // Each kind's realisations sorted: the metric's distribution (a CDF) per tolerance.
    const bool l2 = r.ranked_by == "l2";
    plot::Chart chart{
        .title =
            fmt::format("{}: {} over {} realisations", scene_name,
                        l2 ? fmt::format("{} to the target", metric_name(r.metric)) : "efficiency",
                        r.tolerances.realisations),
        .x = {.label = "share of the realisations"},
        .y = {.label = l2 ? fmt::format("{} ({})", metric_name(r.metric), metric_unit(r.metric))
                          : "efficiency"}};
    std::vector<std::string> kinds{"joint"};
    kinds.insert(kinds.end(), r.active.begin(), r.active.end());
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        std::vector<double> v = metric(r.rows, kinds[k], l2 ? get_l2 : get_efficiency);
        std::sort(v.begin(), v.end());
        plot::Series s{.label = kinds[k], .colour = plot::palette(k), .width = k ? 1.6 : 2.4};
        for (std::size_t i = 0; i < v.size(); ++i) {
            s.x.push_back((double(i) + 0.5) / double(v.size()));
            s.y.push_back(v[i]);
        }
        chart.series.push_back(std::move(s));
    }
    chart.marks.push_back({.vertical = false,
                           .value = l2 ? r.nominal.l2_lm.value_or(0.0) : r.nominal.efficiency,
                           .label = "nominal"});
    return chart;
}

} // namespace fird
