#include "search_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "calibrate/order_statistics.hpp"
#include "evaluation/evaluation.hpp"
#include "evaluation/evaluator.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "model/design_parameters.hpp"
#include "model/surface.hpp"
#include "plot/chart.hpp"

namespace fird {

namespace {

nlohmann::json optional_number(const std::optional<double>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::string stage_label(const StageSummary& s) {
    return fmt::format("{}: {:.0e} rays, {} × {}", s.name, double(s.fidelity.rays),
                       s.fidelity.farfield_w, s.fidelity.farfield_h);
}

} // namespace

nlohmann::json start_report_json(const StartReport& s) {
    nlohmann::json j = {{"kind", s.kind}, {"parameters", s.parameters}};
    if (s.kind != "tailored") return j;
    j["edge_ray"] = s.edge_ray;
    j["rim_polar_deg"] = s.rim_polar_deg;
    j["source_share"] = s.source_share;
    j["reaches_rim"] = s.reaches_rim;
    j["target_share_left_out"] = s.target_share_left_out;
    j["clamped"] = s.clamped;
    j["quick_metric"] = s.quick_metric;
    if (!s.quick_score.empty()) j["quick_score"] = s.quick_score;
    j["refused"] = s.refused;
    j["time_s"] = s.time_s;
    return j;
}

StartReport start_report_from_json(const nlohmann::json& j) {
    StartReport s;
    s.kind = j.at("kind").get<std::string>();
    s.parameters = j.at("parameters").get<std::map<std::string, double>>();
    s.edge_ray = j.value("edge_ray", "");
    s.rim_polar_deg = j.value("rim_polar_deg", 0.0);
    s.source_share = j.value("source_share", 0.0);
    s.reaches_rim = j.value("reaches_rim", true);
    s.target_share_left_out = j.value("target_share_left_out", 0.0);
    s.clamped = j.value("clamped", std::vector<std::string>());
    s.quick_metric = j.value("quick_metric", std::map<std::string, double>());
    s.quick_score = j.value("quick_score", std::map<std::string, double>());
    s.refused = j.value("refused", std::map<std::string, std::string>());
    s.time_s = j.value("time_s", 0.0);
    return s;
}

std::string population_summary(const PopulationReport& p) {
    std::string runs;
    for (const PopulationReport::Run& run : p.runs)
        runs += fmt::format(
            "{}{} {:.4g} -> {:.4g}{}", runs.empty() ? "; runs (best, polished): " : ", ",
            run.method, run.before_polish, run.polished,
            run.long_steps > 0 ? fmt::format(" ({} long steps)", run.long_steps) : "");
    if (p.size == 0) // auto's Levenberg-Marquardt runs alone: no population was drawn
        return fmt::format("Levenberg-Marquardt only{}", runs);
    return fmt::format(
        "{} of {}, {} generations, heights sampled {}{}", p.algorithm, p.size, p.generations,
        p.modes > 0 ? "as the " + p.modes_grid + " grid's cosine modes" : "each on its own", runs);
}

std::string levenberg_summary(const LevenbergReport& l) {
    std::string grids;
    for (const std::string& g : l.model_grids)
        grids += (grids.empty() ? "" : ", then ") + g;
    return fmt::format(
        "Levenberg-Marquardt, {} Jacobians and {} damped steps on the far field ({}{}); {}",
        l.jacobians, l.iterations, grids.empty() ? "no model" : grids,
        l.modes > 0 ? fmt::format("; {} modes, up to degree {}", l.modes, l.degree) : "",
        l.verdict);
}

nlohmann::json search_json(const SearchResult& r) {
    nlohmann::json stages = nlohmann::json::array();
    for (const StageSummary& s : r.stages)
        stages.push_back({{"stage", s.name},
                          {"rays", s.fidelity.rays},
                          {"seed", s.fidelity.seed},
                          {"farfield", {s.fidelity.farfield_w, s.fidelity.farfield_h}},
                          {"heightfield", {s.fidelity.heightfield_w, s.fidelity.heightfield_h}},
                          {"evaluations", s.evaluations},
                          {"infeasible", s.infeasible},
                          {"traced", s.traced},
                          {"ms_per_evaluation", s.traced ? s.traced_ms / double(s.traced) : 0.0},
                          {"best_l2", s.best ? nlohmann::json(s.best_l2_lm) : nullptr}});
    nlohmann::json flat = nlohmann::json::array();
    for (const FlatDirection& d : r.flat_directions)
        flat.push_back({{"parameters", d.parameters},
                        {"invariant", d.invariant},
                        {"held", d.held},
                        {"message", describe(d)}});
    nlohmann::json lattice = nullptr;
    if (r.lattice) {
        const LatticeCheck& c = *r.lattice;
        const auto named = [&](const std::vector<double>& x) {
            nlohmann::json p = nlohmann::json::object();
            for (std::size_t k = 0; k < x.size() && k < r.names.size(); ++k)
                p[r.names[k]] = x[k];
            return p;
        };
        nlohmann::json not_polled = nlohmann::json::array();
        for (const auto& x : c.not_polled)
            not_polled.push_back(named(x));
        lattice = {{"point", c.x.empty() ? nlohmann::json(nullptr) : named(c.x)},
                   {"stage", c.stage},
                   {"neighbours", c.neighbours},
                   {"polled", c.polled},
                   {"lower", c.better},
                   {"not_polled", not_polled},
                   {"confirm_l2", optional_number(c.confirm_l2_lm)},
                   {"confirm_noise_l2", optional_number(c.confirm_noise_l2_lm)},
                   {"confirm_noise_limit", optional_number(c.confirm_noise_limit_lm)},
                   {"verdict", c.verdict}};
        if (r.refine && !r.refine->starts.empty()) {
            nlohmann::json starts = nlohmann::json::array();
            for (const auto& x : r.refine->starts)
                starts.push_back(named(x));
            lattice["refined_from"] = named(r.refine->starts.front());
            lattice["refine_starts"] = starts;
            lattice["refine_noise_l2"] = r.refine->noise_l2_lm;
            lattice["refine_noise_limit"] = r.refine->noise_limit_lm;
            lattice["refine_verdict"] = r.refine->verdict;
        }
    }
    nlohmann::json best = nlohmann::json::object();
    for (const auto& [k, v] : r.best_parameters)
        best[k] = v;
    nlohmann::json population = nullptr;
    if (r.population) {
        const PopulationReport& p = *r.population;
        nlohmann::json spread = nlohmann::json::object();
        for (std::size_t k = 0; k < p.spread.size() && k < r.names.size(); ++k)
            spread[r.names[k]] = p.spread[k];
        nlohmann::json runs = nlohmann::json::array();
        for (const PopulationReport::Run& run : p.runs)
            runs.push_back({{"method", run.method},
                            {"seed", run.seed},
                            {"generations", run.generations},
                            {"candidates", run.candidates},
                            {"before_polish", run.before_polish},
                            {"polished", run.polished},
                            {"noise_limit", run.noise_limit},
                            {"long_steps", run.long_steps}});
        population = {{"algorithm", p.algorithm},
                      {"size", p.size},
                      {"generations", p.generations},
                      {"sigma0", p.sigma0},
                      {"seed", p.seed},
                      {"spread_steps", spread},
                      {"height_sampling", p.modes > 0 ? "modes" : "independent"},
                      {"modes", p.modes},
                      {"modes_grid", p.modes_grid},
                      {"runs", runs},
                      {"verdict", p.verdict}};
    }
    nlohmann::json levenberg = nullptr;
    if (r.levenberg)
        levenberg = {{"modes", r.levenberg->modes},
                     {"degree", r.levenberg->degree},
                     {"iterations", r.levenberg->iterations},
                     {"jacobians", r.levenberg->jacobians},
                     {"model_grids", r.levenberg->model_grids},
                     {"verdict", r.levenberg->verdict}};
    nlohmann::json constraints = nlohmann::json::array();
    for (const ConstraintAtOptimum& c : r.constraints)
        constraints.push_back({{"name", c.name},
                               {"value", c.value},
                               {"limit", c.limit},
                               {"met", c.met},
                               {"active", c.active},
                               {"active_by", c.active ? nlohmann::json(c.active_by) : nullptr}});
    const auto photometry = [](const std::optional<Photometrics>& p) {
        return p ? photometrics_json(*p) : nlohmann::json(nullptr);
    };
    nlohmann::json smoothness = nullptr;
    if (r.smoothness_weight > 0.0) {
        // The penalty the best pays, and its score on the final fresh-ray l2.
        const std::optional<double> penalty =
            r.best_bending_energy
                ? std::optional<double>(r.smoothness_weight * *r.best_bending_energy)
                : std::nullopt;
        smoothness = {{"weight", r.smoothness_weight},
                      {"start_bending_energy", optional_number(r.start_bending_energy)},
                      {"best_bending_energy", optional_number(r.best_bending_energy)},
                      {"best_penalty", optional_number(penalty)},
                      {"final_score", r.final_l2_lm && penalty
                                          ? nlohmann::json(*r.final_l2_lm + *penalty)
                                          : nlohmann::json(nullptr)}};
    }
    nlohmann::json start = start_report_json(r.start);
    start["metric_at_start"] = optional_number(r.start_l2_lm);
    return {{"method", r.method},
            {"backend", r.backend},
            {"start", start},
            {"metric", r.metric},
            {"metric_unit", r.metric_unit},
            {"photometrics", photometry(r.photometrics)},
            {"desired_photometrics", photometry(r.desired_photometrics)},
            {"evaluations", r.history.size()},
            {"infeasible", r.infeasible},
            {"best_parameters", best},
            {"best_evaluation", r.best ? nlohmann::json(*r.best) : nullptr},
            {"best_l2", r.best ? nlohmann::json(r.best_l2_lm) : nullptr},
            {"best_score", r.best ? nlohmann::json(r.best_score) : nullptr},
            {"smoothness", smoothness},
            {"start_l2", optional_number(r.start_l2_lm)},
            {"final_l2", optional_number(r.final_l2_lm)},
            {"noise_floor_l2", optional_number(r.noise_floor_l2_lm)},
            {"surface_rms_mm", optional_number(r.surface_rms_mm)},
            {"rays_per_evaluation", stages},
            {"grid_size", r.grid_size},
            {"flat_directions", flat},
            {"lattice", lattice},
            {"population", population},
            {"levenberg", levenberg},
            {"constraints", constraints},
            {"desired", r.desired},
            {"time_s", r.time_s},
            {"stopped", stop_reason_name(r.stopped)}};
}

nlohmann::json search_options_json(const SearchSettings& s, const Scene& scene,
                                   const StartReport& start) {
    return {{"method", method_name(s.method)},
            {"rays", s.rays},
            {"threshold_lm", s.threshold_lm},
            {"max_evaluations", s.max_evaluations},
            {"seed", s.seed},
            {"refine", s.refine},
            {"backend", backend_name(s.backend)},
            {"scene", scene_to_toml(scene)},
            {"scene_path", std::filesystem::absolute(scene.path).lexically_normal().string()},
            {"start", start_report_json(start)}};
}

void write_progress_png(const std::string& out, const SearchResult& r) {
    const ProgressCharts charts = progress_charts(r);
    const int cols = 2, rows = int((charts.parameters.size() + 1) / 2);
    const double w = 1100.0, top_h = 440.0, panel_h = 250.0;
    plot::Canvas cv(int(w), int(top_h + rows * panel_h));
    plot::draw_chart(cv, {0, 0, w, top_h}, charts.l2);
    for (std::size_t k = 0; k < charts.parameters.size(); ++k)
        plot::draw_chart(
            cv,
            {double(k % cols) * w / cols, top_h + double(k / cols) * panel_h, w / cols, panel_h},
            charts.parameters[k]);
    cv.write_png(out);
}

ProgressCharts progress_charts(const SearchResult& r) {
    ProgressCharts out;
    // Evaluations from 0, at least ten wide (whole numbers from the first point).
    double last = double(r.history.size());
    for (const Candidate& c : r.history)
        last = std::max(last, double(c.index) + 1.0);
    const plot::Axis evaluations{.label = "evaluation", .min = 0.0, .max = std::max(10.0, last)};
    // Every candidate's score (its l2, plus the smoothness penalty when weighted),
    // coloured by stage, and each stage's best so far.
    const std::string scored =
        r.smoothness_weight > 0.0
            ? fmt::format("{} + {:g} x bending energy", r.metric, r.smoothness_weight)
            : r.metric;
    plot::Chart& l2 = out.l2;
    l2 = {.title =
              fmt::format("Search progress ({}): {} of each reflector tested", r.method, scored),
          .x = evaluations,
          .y = {fmt::format("{} ({})",
                            r.smoothness_weight > 0.0 ? scored
                                                      : r.metric + " to the desired far field",
                            r.metric_unit),
                plot::Scale::Log}};
    for (std::size_t s = 0; s < r.stages.size(); ++s) {
        plot::Series points{.kind = plot::Series::Kind::Points,
                            .label = stage_label(r.stages[s]),
                            .colour = plot::palette(s)};
        plot::Series best{.colour = plot::palette(s), .width = 2.2};
        double running = HUGE_VAL;
        for (const Candidate& c : r.history) {
            if (c.stage != s || !c.feasible) continue;
            points.x.push_back(double(c.index));
            points.y.push_back(c.score);
            points.radius_px.push_back(2.5);
            running = std::min(running, c.score);
            best.x.push_back(double(c.index));
            best.y.push_back(running);
        }
        l2.series.push_back(std::move(points));
        l2.series.push_back(std::move(best));
    }
    // A population search: each generation's spread, the 10-90 % quantile of its feasible
    // candidates' scores (each candidate carries its generation; answers from the memo add
    // none), flat across the generation's evaluations and shaded behind the points: it
    // narrows as the population converges.
    plot::Series band{.kind = plot::Series::Kind::Band,
                      .label = "each generation's 10-90 %",
                      .colour = {0.55, 0.55, 0.65, 0.25}};
    for (std::size_t first = 0; first < r.history.size();) {
        const Candidate& c = r.history[first];
        std::size_t end = first + 1; // the generation's rows: [first, end)
        while (end < r.history.size() && r.history[end].generation == c.generation &&
               r.history[end].stage == c.stage)
            ++end;
        std::vector<double> scores;
        for (std::size_t k = first; k < end; ++k)
            if (r.history[k].feasible) scores.push_back(r.history[k].score);
        if (c.generation && scores.size() >= 2) {
            std::sort(scores.begin(), scores.end());
            for (const std::size_t k : {first, end - 1}) {
                band.x.push_back(double(r.history[k].index));
                band.y.push_back(sorted_quantile(scores, 0.1));
                band.y_upper.push_back(sorted_quantile(scores, 0.9));
            }
        }
        first = end;
    }
    if (!band.x.empty()) l2.series.insert(l2.series.begin(), std::move(band));
    if (r.final_l2_lm) {
        // On the scores' axis: the final l2 plus the best's penalty.
        const double penalty =
            r.best_bending_energy ? r.smoothness_weight * *r.best_bending_energy : 0.0;
        l2.marks.push_back({.vertical = false,
                            .value = *r.final_l2_lm + penalty,
                            .label = fmt::format("final {} {:.4g} {} (fresh rays)", scored,
                                                 *r.final_l2_lm + penalty, r.metric_unit),
                            .colour = plot::kInk});
    }
    if (r.noise_floor_l2_lm)
        l2.marks.push_back(
            {.vertical = false,
             .value = *r.noise_floor_l2_lm,
             .label = fmt::format("noise floor {:.4g} {}", *r.noise_floor_l2_lm, r.metric_unit),
             .colour = {0.5, 0.5, 0.5}});
    // Each parameter: every candidate's value (grey) and the best so far (the path).
    for (std::size_t k = 0; k < r.names.size(); ++k) {
        plot::Chart p{.title = r.names[k], .x = evaluations, .y = {r.names[k]}, .legend = false};
        if (k < r.bounds.size()) {
            // The box, a little wider so candidates on its edges stay visible.
            const auto [lo, hi] = r.bounds[k];
            const double pad = hi > lo ? 0.04 * (hi - lo) : std::max(1.0, 0.05 * std::abs(lo));
            p.y.min = lo - pad, p.y.max = hi + pad;
        }
        plot::Series tried{.kind = plot::Series::Kind::Points, .colour = {0.6, 0.6, 0.6}};
        plot::Series path{.colour = plot::palette(0), .width = 2.2};
        double best = HUGE_VAL;
        std::uint32_t stage = 0;
        for (const Candidate& c : r.history) {
            tried.x.push_back(double(c.index));
            tried.y.push_back(c.x[k]);
            tried.radius_px.push_back(c.feasible ? 2.0 : 1.2);
            if (c.stage != stage) stage = c.stage, best = HUGE_VAL; // l2 of a new stage
            if (c.feasible && c.score < best) {
                best = c.score;
                if (!path.x.empty()) {
                    path.x.push_back(double(c.index));
                    path.y.push_back(path.y.back());
                }
                path.x.push_back(double(c.index));
                path.y.push_back(c.x[k]);
            }
        }
        if (!path.x.empty()) {
            path.x.push_back(double(r.history.size()));
            path.y.push_back(path.y.back());
        }
        p.series = {std::move(tried), std::move(path)};
        const auto it = r.best_parameters.find(r.names[k]);
        if (it != r.best_parameters.end())
            p.marks.push_back({.vertical = false,
                               .value = it->second,
                               .label = fmt::format("best {:.4g}", it->second),
                               .colour = plot::palette(1)});
        out.parameters.push_back(std::move(p));
    }
    return out;
}

std::string best_scene_toml(const Scene& scene, const SearchResult& r) {
    // Its files found from the output folder too.
    Scene best = with_absolute_files(scene);
    apply_design_parameters(best, r.best_parameters);
    std::string text = fmt::format(
        "# {}: the best reflector of fird optimize ({}, {} {:.6g} {} at evaluation {})\n",
        one_line(scene.name), r.method, r.metric, r.best_l2_lm, r.metric_unit,
        r.best ? *r.best : 0);
    return text + scene_to_toml(best);
}

plot::Chart start_profiles_chart(const Scene& scene, const SearchResult& r) {
    plot::Chart chart{.title = fmt::format("The profile z(r): the {} start ({} edge rays) and "
                                           "the best",
                                           r.start.kind, r.start.edge_ray),
                      .x = {"r (mm) from the axis"},
                      .y = {"z (mm)"}};
    const auto series = [&](const std::string& label, const std::map<std::string, double>& named,
                            std::size_t colour) {
        Scene s = scene;
        apply_design_parameters(s, named);
        const Surface surface = Surface::make(s.reflector, s.holder);
        const auto& p = s.reflector.parameters;
        const double cx = p.at("cx"), cy = p.at("cy"), radius = p.at("radius_mm");
        plot::Series line{.label = label, .colour = plot::palette(colour)};
        for (int i = 0; i <= 200; ++i) {
            const double rr = radius * i / 200.0;
            line.x.push_back(rr);
            line.y.push_back(surface.height(cx + rr, cy));
        }
        chart.series.push_back(std::move(line));
    };
    series("the scene's start", {}, 0);
    series(fmt::format("the start ({})", r.start.kind), r.start.parameters, 1);
    if (r.best) series("the best", r.best_parameters, 2);
    chart.marks.push_back({.vertical = false,
                           .value = scene.source.center_mm.z,
                           .label = "the source's centre",
                           .colour = {0.5, 0.5, 0.5}});
    return chart;
}

void write_search_outputs(const std::string& dir, const Scene& scene, const SearchOutcome& o) {
    namespace fs = std::filesystem;
    create_output_directory(dir);
    const auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
    const SearchResult& r = o.result;
    write_text_file(path("search.json"), search_json(r).dump(2) + "\n");
    write_progress_png(path("progress.png"), r);
    if (r.start.kind == "tailored" && scene.reflector.family == Family::Profile)
        plot::write_chart_png(path("profiles.png"), start_profiles_chart(scene, r));
    if (!r.best) return;
    Scene best = scene;
    best.name = scene.name + " (best)";
    write_text_file(path("best.toml"), best_scene_toml(scene, r));
    if (!o.best_farfield) return;
    Evaluation e;
    e.backend = "gpu";
    e.farfield = *o.best_farfield;
    e.target_farfield = o.desired.farfield;
    e.l2_lm = r.final_l2_lm;
    e.tally.emitted = scene.trace.rays;
    write_evaluation_outputs(dir, best, e, "fird optimize (best reflector)");
}

} // namespace fird
