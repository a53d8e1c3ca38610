#include "calibration_report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "plot/chart.hpp"

namespace fird {

namespace {

std::string in_dir(const std::string& dir, const std::string& name) {
    return (std::filesystem::path(dir) / name).string();
}

nlohmann::json finite_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json fit_json(const VariogramFit& f) {
    return {{"type", variogram_model_name(f.model)},
            {"nugget", f.nugget},
            {"sill", f.sill},
            {"range", f.range},
            {"residual", f.residual}};
}

// The resolvable step's probes: each lag with its signal, the spread of its common-random-
// number differences and the verdict at the stated confidence.
nlohmann::json resolution_json(const std::vector<ResolutionProbe>& probes) {
    nlohmann::json a = nlohmann::json::array();
    for (const ResolutionProbe& p : probes)
        a.push_back({{"lag", p.lag},
                     {"signal_lm", p.signal_lm},
                     {"noise_sd_lm", finite_or_null(p.noise_sd_lm)},
                     {"differences", p.differences},
                     {"ties", p.ties},
                     {"resolved", p.resolved}});
    return a;
}

} // namespace

plot::Chart rays_table_chart(const RaysTable& t, const std::string& scene) {
    plot::Chart c{.title = fmt::format("{}: {} error against rays (Table 1, {} sampler)", scene,
                                       metric_name(t.metric), sampler_name(t.sampler)),
                  .x = {"rays", plot::Scale::Log},
                  .y = {fmt::format("{} to the desired far field ({})", metric_name(t.metric),
                                    metric_unit(t.metric)),
                        plot::Scale::Log}};
    plot::Series band{.kind = plot::Series::Kind::Band,
                      .label = "mean ± one standard deviation",
                      .colour = plot::palette(0)};
    plot::Series mean{
        .kind = plot::Series::Kind::Line, .label = "mean", .colour = plot::palette(0)};
    plot::Series points{.kind = plot::Series::Kind::Points, .colour = plot::palette(0)};
    plot::Series predicted{.label = "prediction: " + noise_prediction_label(t.sampler),
                           .colour = plot::palette(1),
                           .dashed = true};
    // For any other sampler the independent rays' formula is drawn too, as what it is: the
    // noise of the `random` sampler, above the stratified sampler's.
    plot::Series multinomial{.label = "independent rays (multinomial formula)",
                             .colour = plot::palette(2),
                             .dashed = true};
    for (const RaysRow& r : t.rows) {
        const double sd = std::sqrt(r.var_l2);
        band.x.push_back(double(r.rays));
        band.y.push_back(std::max(r.mean_l2 - sd, 1e-3 * r.mean_l2));
        band.y_upper.push_back(r.mean_l2 + sd);
        for (plot::Series* s : {&mean, &points})
            s->x.push_back(double(r.rays));
        mean.y.push_back(r.mean_l2);
        points.y.push_back(r.mean_l2);
        if (std::isfinite(r.predicted_l2)) {
            predicted.x.push_back(double(r.rays));
            predicted.y.push_back(r.predicted_l2);
        }
        multinomial.x.push_back(double(r.rays));
        multinomial.y.push_back(r.multinomial_l2);
    }
    c.series = {band, mean, points, predicted};
    if (t.prediction != NoisePrediction::Multinomial) c.series.push_back(multinomial);
    return c;
}

nlohmann::json rays_table_json(const RaysTable& t) {
    nlohmann::json rows = nlohmann::json::array();
    for (const RaysRow& r : t.rows)
        rows.push_back({{"rays", r.rays},
                        {"runs", r.runs},
                        {"mean_l2", r.mean_l2},
                        {"var_l2", r.var_l2},
                        {"predicted_l2", finite_or_null(r.predicted_l2)},
                        {"multinomial_l2", r.multinomial_l2},
                        {"replicate_l2", finite_or_null(r.replicate_l2)},
                        {"replicate_pairs", r.replicate_pairs},
                        {"time_s", r.time_s}});
    return {{"rows", rows},
            {"metric", metric_name(t.metric)},
            {"metric_unit", metric_unit(t.metric)},
            {"desired_rays", t.desired_rays ? nlohmann::json(t.desired_rays) : nullptr},
            {"desired", t.desired},
            {"sampler", sampler_name(t.sampler)},
            {"prediction", noise_prediction_name(t.prediction)},
            {"prediction_label", noise_prediction_label(t.sampler)},
            {"slope", t.slope},
            {"time_s", t.time_s}};
}

std::string rays_table_markdown(const RaysTable& t, const std::string& scene) {
    std::string s = fmt::format("{}: l2 of independent simulations of the desired reflector "
                                "against {} ({} sampler, {:.1f} s in all)\n\n"
                                "Predicted: {}. Multinomial: the formula for independent rays "
                                "(random sampler). Replicate: measured from pairs of runs.\n\n",
                                scene, t.desired, sampler_name(t.sampler), t.time_s,
                                noise_prediction_label(t.sampler));
    s += "| Rays | Mean l2 error | Variance l2 error | Predicted | Multinomial | Replicate | "
         "Runs | s |\n";
    s += "|---|---|---|---|---|---|---|---|\n";
    for (const RaysRow& r : t.rows)
        s += fmt::format("| {} | {:.4g} | {:.3g} | {:.4g} | {:.4g} | {:.4g} | {} | {:.1f} |\n",
                         r.rays, r.mean_l2, r.var_l2, r.predicted_l2, r.multinomial_l2,
                         r.replicate_l2, r.runs, r.time_s);
    s += fmt::format("\nSlope of log mean against log rays: {:.3f} (-0.5 where noise "
                     "dominates).\n",
                     t.slope);
    return s;
}

void write_rays_table(const std::string& dir, const RaysTable& t, const std::string& scene) {
    create_output_directory(dir);
    // New columns go last, so that readers by position keep working; the prediction's
    // sampler and kind are on every row.
    std::string csv = "rays,runs,mean_l2_lm,var_l2_lm2,predicted_l2_lm,time_s,multinomial_l2_lm,"
                      "replicate_l2_lm,replicate_pairs,sampler,prediction\n";
    const auto number = [](double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : ""; };
    for (const RaysRow& r : t.rows)
        csv += fmt::format("{},{},{:.9g},{:.9g},{},{:.3f},{:.9g},{},{},{},{}\n", r.rays, r.runs,
                           r.mean_l2, r.var_l2, number(r.predicted_l2), r.time_s, r.multinomial_l2,
                           number(r.replicate_l2), r.replicate_pairs, sampler_name(t.sampler),
                           noise_prediction_name(t.prediction));
    write_text_file(in_dir(dir, "table1.csv"), csv);
    write_text_file(in_dir(dir, "table1.md"), rays_table_markdown(t, scene));
    write_text_file(in_dir(dir, "calibration.json"), rays_table_json(t).dump(2) + "\n");
    plot::write_chart_png(in_dir(dir, "table1.png"), rays_table_chart(t, scene));
}

plot::Chart semivariogram_chart(const ParameterSemivariogram& p, std::uint64_t rays,
                                const std::string& scene, FarFieldMetric metric) {
    // Figure 8: points sized by their pair count, the fitted curve, range and nugget.
    plot::Chart c{.title = fmt::format("{}: semivariogram of {} along {} ({:.0e} rays)", scene,
                                       metric_name(metric), p.parameter, double(rays)),
                  .x = {"lag h (" + p.parameter + ")", plot::Scale::Linear},
                  .y = {fmt::format("γ(h) ({}²)", metric_unit(metric)), plot::Scale::Linear}};
    plot::Series pts{.kind = plot::Series::Kind::Points,
                     .label = "empirical (size: pairs)",
                     .colour = plot::palette(0)};
    const double most =
        double(*std::max_element(p.empirical.pairs.begin(), p.empirical.pairs.end()));
    for (std::size_t k = 0; k < p.empirical.lags.size(); ++k) {
        pts.x.push_back(p.empirical.lags[k]);
        pts.y.push_back(p.empirical.gamma[k]);
        pts.radius_px.push_back(2.0 + 4.0 * std::sqrt(double(p.empirical.pairs[k]) / most));
    }
    plot::Series curve{.label = fmt::format("{} model", variogram_model_name(p.model.model)),
                       .colour = plot::palette(1),
                       .width = 2.2};
    const double top = p.empirical.lags.back();
    for (int i = 0; i <= 200; ++i) {
        const double h = top * i / 200.0;
        curve.x.push_back(h);
        curve.y.push_back(i == 0 ? p.model.nugget : variogram(p.model, h));
    }
    c.series = {pts, curve};
    c.marks = {{.vertical = true,
                .value = p.model.range,
                .label = fmt::format("range {:.3g}", p.model.range),
                .colour = plot::palette(2)},
               {.vertical = false,
                .value = p.model.nugget,
                .label = fmt::format("nugget {:.3g}", p.model.nugget),
                .colour = {0.45, 0.45, 0.45}},
               {.vertical = false,
                .value = p.model.sill,
                .label = fmt::format("sill {:.3g}", p.model.sill),
                .colour = {0.45, 0.45, 0.45}}};
    if (p.resolvable_step)
        c.marks.push_back({.vertical = true,
                           .value = *p.resolvable_step,
                           .label = fmt::format("resolvable {:.3g} ({:.0f} %)", *p.resolvable_step,
                                                100.0 * kOrderingConfidence),
                           .colour = plot::palette(3)});
    return c;
}

nlohmann::json semivariogram_json(const SemivariogramResult& r) {
    nlohmann::json params = nlohmann::json::array();
    for (const ParameterSemivariogram& p : r.parameters) {
        nlohmann::json l2 = nlohmann::json::array();
        for (double v : p.l2)
            l2.push_back(finite_or_null(v));
        nlohmann::json fits = nlohmann::json::array();
        for (const VariogramFit& f : p.fits)
            fits.push_back(fit_json(f));
        params.push_back({{"parameter", p.parameter},
                          {"series", {{"x", p.x}, {"l2", l2}}},
                          {"lags", p.empirical.lags},
                          {"gamma", p.empirical.gamma},
                          {"pairs", p.empirical.pairs},
                          {"model", fit_json(p.model)},
                          {"models", fits},
                          {"recommended_step", p.recommended_step},
                          {"resolvable_step", p.resolvable_step ? nlohmann::json(*p.resolvable_step)
                                                                : nlohmann::json(nullptr)},
                          {"resolution", resolution_json(p.resolution)},
                          {"calibrated_step", calibrated_step(p, r.step_rule)},
                          {"time_s", p.time_s}});
    }
    return {{"parameters", params},
            {"metric", metric_name(r.metric)},
            {"metric_unit", metric_unit(r.metric)},
            {"rays", r.rays},
            {"points", r.points},
            {"desired", r.desired},
            {"noise_variance_l2", r.noise_variance_l2},
            {"noise_runs", r.noise_runs},
            {"step_rule", step_rule_name(r.step_rule)},
            {"ordering_confidence", kOrderingConfidence},
            {"time_s", r.time_s}};
}

void write_semivariograms(const std::string& dir, const SemivariogramResult& r,
                          const std::string& scene) {
    create_output_directory(dir);
    std::string series = "parameter,x,l2_lm\n", sv = "parameter,lag,gamma_lm2,pairs,model_lm2\n";
    std::string resolution = "parameter,lag,signal_lm,noise_sd_lm,differences,ties,resolved\n";
    for (const ParameterSemivariogram& p : r.parameters) {
        for (std::size_t i = 0; i < p.x.size(); ++i)
            series += fmt::format("{},{:.9g},{}\n", p.parameter, p.x[i],
                                  std::isfinite(p.l2[i]) ? fmt::format("{:.9g}", p.l2[i]) : "");
        for (std::size_t k = 0; k < p.empirical.lags.size(); ++k)
            sv += fmt::format("{},{:.9g},{:.9g},{},{:.9g}\n", p.parameter, p.empirical.lags[k],
                              p.empirical.gamma[k], p.empirical.pairs[k],
                              variogram(p.model, p.empirical.lags[k]));
        for (const ResolutionProbe& q : p.resolution)
            resolution += fmt::format(
                "{},{:.9g},{:.9g},{},{},{},{}\n", p.parameter, q.lag, q.signal_lm,
                std::isfinite(q.noise_sd_lm) ? fmt::format("{:.9g}", q.noise_sd_lm) : "",
                q.differences, q.ties, q.resolved ? 1 : 0);
        plot::write_chart_png(in_dir(dir, "semivariogram_" + p.parameter + ".png"),
                              semivariogram_chart(p, r.rays, scene, r.metric));
    }
    write_text_file(in_dir(dir, "series.csv"), series);
    write_text_file(in_dir(dir, "semivariogram.csv"), sv);
    write_text_file(in_dir(dir, "resolution.csv"), resolution);
    write_text_file(in_dir(dir, "calibration.json"), semivariogram_json(r).dump(2) + "\n");
}

} // namespace fird
