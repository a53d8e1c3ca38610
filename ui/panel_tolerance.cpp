// The calibrate panel's tolerance section (issue 27 item 4): fird tolerance's realisations
// of the open scene, its [tolerance] table edited in a form, the spreads as a table beside
// the nominal luminaire and each tolerance's distribution as a chart.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <fmt/format.h>
#include <imgui.h>

#include "chart_widget.hpp"
#include "io/parse_number.hpp"
#include "model/source.hpp"
#include "model/tolerance_check.hpp"
#include "panels.hpp"

namespace fird::ui {

// What the panel shows of the worker's run: copied from it, and the spreads and chart made,
// once per change of its progress, never per frame.
struct ToleranceView {
    ToleranceProgress progress;
    nlohmann::json summary; // tolerance_json of the result
    plot::Chart chart;      // tolerance_chart of the result
};

namespace {

// The seeds the form and the script take: whole numbers a double holds exactly.
constexpr std::uint64_t kMaxSeed = std::uint64_t(1) << 53;

// A scene without a [tolerance] table gets a part made to common press and assembly
// tolerances: the LED placed within 0.1 mm per axis and tilted 1 degree (where it has an
// axis), 16 realisations per run.
ToleranceDesc default_tolerances(const Scene& scene) {
    ToleranceDesc t{.realisations = 16, .source_shift_mm = glm::dvec3(0.1)};
    if (source_has_axis(scene.source)) t.source_tilt_deg = 1.0;
    return t;
}

// The form follows the open scene: filled again when another scene is opened, or the same
// one with another [tolerance] table. A table that gives no tolerance keeps its
// realisations beside the defaults.
void fill_form(WorkbenchState& s) {
    auto& form = s.tolerance_form;
    if (!s.editor.scene) return;
    const ToleranceDesc& table = s.editor.scene->tolerance;
    if (form.filled_from == s.editor.path && form.filled_with == table) return;
    if (active_tolerances(table).empty()) {
        form.tolerances = default_tolerances(*s.editor.scene);
        if (table != ToleranceDesc{}) form.tolerances.realisations = table.realisations;
    } else {
        form.tolerances = table;
    }
    form.filled_from = s.editor.path;
    form.filled_with = table;
}

// Why Start is refused, in a line (empty when it is not).
std::string start_problem(WorkbenchState& s) {
    if (!s.editor.scene) return "no scene is open";
    const ToleranceDesc& t = s.tolerance_form.tolerances;
    if (const auto problem = tolerance_problem(t, s.editor.scene->source))
        return problem->key + ": " + problem->reason;
    if (active_tolerances(t).empty()) return "no tolerance given (every one is 0)";
    return "";
}

bool input_mm(const char* label, double& v, const char* format = "%.3f") {
    ImGui::SetNextItemWidth(80);
    const bool changed =
        ImGui::InputScalar(label, ImGuiDataType_Double, &v, nullptr, nullptr, format);
    if (changed) v = std::isfinite(v) ? std::max(v, 0.0) : 0.0;
    return changed;
}

void form(WorkbenchState& s) {
    ToleranceDesc& t = s.tolerance_form.tolerances;
    int realisations = int(std::min<std::uint64_t>(t.realisations, 1000000));
    ImGui::SetNextItemWidth(80);
    if (ImGui::InputInt("realisations", &realisations))
        t.realisations = std::uint64_t(std::clamp(realisations, 1, 1000000));
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    std::uint64_t seed = s.tolerance_form.seed;
    if (ImGui::InputScalar("seed", ImGuiDataType_U64, &seed))
        s.tolerance_form.seed = std::min<std::uint64_t>(seed, kMaxSeed);
    ImGui::SetNextItemWidth(200);
    if (ImGui::InputScalarN("source shift (mm, sd per axis)", ImGuiDataType_Double,
                            &t.source_shift_mm.x, 3, nullptr, nullptr, "%.3f"))
        for (int k = 0; k < 3; ++k)
            t.source_shift_mm[k] =
                std::isfinite(t.source_shift_mm[k]) ? std::max(t.source_shift_mm[k], 0.0) : 0.0;
    input_mm("tilt (deg)", t.source_tilt_deg, "%.2f");
    ImGui::SameLine();
    input_mm("reflectance sd", t.reflectance_sd);
    input_mm("surface rms (mm)", t.surface_rms_mm);
    ImGui::SameLine();
    input_mm("correlation (mm)", t.surface_correlation_mm, "%.1f");
}

// The spreads of the result: one row per measure, the nominal luminaire beside them; a
// dash where a run has no feasible realisation (or was stopped before it).
void spreads_table(const ToleranceResult& r, const nlohmann::json& j) {
    struct Row {
        const char* key;
        std::string label;
    };
    std::vector<Row> rows;
    if (j.contains("l2"))
        rows.push_back({"l2", fmt::format("{} ({})", j["metric"].get<std::string>(),
                                          j["metric_unit"].get<std::string>())});
    rows.push_back({"efficiency", "efficiency"});
    rows.push_back({"peak_cd", "peak (cd)"});
    rows.push_back({"beam_angle_deg", "beam angle (deg)"});
    if (ImGui::BeginTable("##spreads", 5,
                          ImGuiTableFlags_Borders | ImGuiTableFlags_SizingFixedFit)) {
        for (const char* h : {"joint run", "nominal", "median", "5 %", "95 %"})
            ImGui::TableSetupColumn(h);
        ImGui::TableHeadersRow();
        for (const Row& row : rows) {
            ImGui::TableNextRow();
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(row.label.c_str());
            ImGui::TableNextColumn();
            ImGui::Text("%.4g", j["nominal"].value(row.key, 0.0));
            for (const char* q : {"median", "p5", "p95"}) {
                ImGui::TableNextColumn();
                if (j[row.key].is_null())
                    ImGui::TextUnformatted("-");
                else
                    ImGui::Text("%.4g", j[row.key][q].get<double>());
            }
        }
        ImGui::EndTable();
    }
    // One-at-a-time: how far each tolerance alone spreads the ranked measure.
    const char* ranked = j.contains("l2") ? "l2" : "efficiency";
    std::string line = fmt::format("{} 5-95 % by tolerance alone:", ranked);
    for (const auto& s : j["sensitivities"]) {
        const auto& m = s[ranked];
        if (m.is_null()) {
            line += fmt::format("  {} -", s["tolerance"].get<std::string>());
            continue;
        }
        line += fmt::format("  {}{} {:.3g}", s["tolerance"].get<std::string>(),
                            s["tolerance"] == j["most_sensitive"] ? " (most)" : "",
                            m["p95"].get<double>() - m["p5"].get<double>());
    }
    ImGui::TextWrapped("%s", line.c_str());
    if (r.infeasible > 0)
        ImGui::TextWrapped("%llu realisations left out: the source left the footprint or "
                           "touched the surface",
                           static_cast<unsigned long long>(r.infeasible));
}

} // namespace

void start_tolerance(Frame& f) {
    WorkbenchState& s = f.state;
    fill_form(s);
    if (const std::string why = start_problem(s); !why.empty())
        return add_log(s, "error: tolerance: " + why);
    // One run at a time: a second would replace the first's figures under its scene name.
    if (f.worker.tolerance_pending())
        return add_log(s, "error: tolerance: a tolerance run is already running or waiting");
    const ToleranceDesc& t = s.tolerance_form.tolerances;
    const std::string out = new_run_folder(s, "tolerance");
    if (out.empty()) return; // the error is in the log
    f.worker.submit(ToleranceJob{
        .scene = edited_scene(s), .tolerances = t, .seed = s.tolerance_form.seed, .out_dir = out});
    s.tolerance_form.last_scene = s.editor.path;
    add_log(s, "tolerance started; files in " + out);
}

std::string set_tolerance_field(WorkbenchState& s, const std::string& key,
                                const std::string& value) {
    if (!s.editor.scene) return "no scene is open";
    fill_form(s);
    ToleranceDesc& t = s.tolerance_form.tolerances;
    const auto number = [&](const std::string& text) -> double {
        const auto v = parse_finite_number(text);
        if (!v || *v < 0.0) throw std::invalid_argument(key);
        return *v;
    };
    try {
        if (key == "realisations" || key == "seed") {
            const double v = number(value);
            const bool seed = key == "seed";
            const double most = seed ? double(kMaxSeed) : 1e6;
            if (v != std::floor(v) || v > most || (!seed && v < 1))
                return fmt::format("{}: '{}' is not a whole number from {} to {:g}", key, value,
                                   seed ? 0 : 1, most);
            (seed ? s.tolerance_form.seed : t.realisations) = std::uint64_t(v);
        } else if (key == "source_shift_mm") {
            std::vector<double> parts;
            for (std::size_t from = 0; from <= value.size();) {
                const std::size_t comma = std::min(value.find(',', from), value.size());
                parts.push_back(number(value.substr(from, comma - from)));
                from = comma + 1;
            }
            if (parts.size() != 1 && parts.size() != 3)
                return "source_shift_mm: one value or X,Y,Z";
            for (int k = 0; k < 3; ++k)
                t.source_shift_mm[k] = parts[parts.size() == 1 ? 0 : std::size_t(k)];
        } else if (key == "source_tilt_deg") {
            t.source_tilt_deg = number(value);
        } else if (key == "surface_rms_mm") {
            t.surface_rms_mm = number(value);
        } else if (key == "surface_correlation_mm") {
            t.surface_correlation_mm = number(value);
        } else if (key == "reflectance_sd") {
            t.reflectance_sd = number(value);
        } else {
            return fmt::format("no tolerance key '{}' (realisations, seed, source_shift_mm, "
                               "source_tilt_deg, surface_rms_mm, surface_correlation_mm, "
                               "reflectance_sd)",
                               key);
        }
    } catch (const std::invalid_argument&) {
        return fmt::format("{}: '{}' is not a number >= 0", key, value);
    }
    return "";
}

bool tolerance_can_start(WorkbenchState& s) {
    fill_form(s);
    return start_problem(s).empty();
}

void tolerance_section(Frame& f) {
    WorkbenchState& s = f.state;
    fill_form(s);
    auto& view = s.tolerance_form.view;
    if (const std::uint64_t g = f.worker.tolerance_generation();
        !view || view->progress.generation != g) {
        auto v = std::make_shared<ToleranceView>();
        v->progress = f.worker.tolerance();
        if (const auto& r = v->progress.result) {
            v->summary = tolerance_json(*r);
            v->chart = tolerance_chart(v->progress.scene_name, *r);
        }
        view = std::move(v);
    }
    const ToleranceProgress& t = view->progress;
    // Folded away, the results get the panel's height.
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::CollapsingHeader("tolerances (fird tolerance's options)")) {
        ImGui::BeginDisabled(t.running);
        form(s);
        ImGui::EndDisabled();
    }
    if (const std::string why = start_problem(s); !why.empty() && s.editor.scene)
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.4f, 1.0f), "%s", why.c_str());
    if (!t.running && !t.result) return;
    if (s.tolerance_form.last_scene != s.editor.path) {
        // Another scene's realisations: not this scene's figures.
        ImGui::TextWrapped("the last tolerance run was of %s", s.tolerance_form.last_scene.c_str());
        return;
    }
    ImGui::Text("%zu of %zu realisations traced%s", t.rows.size(), t.total,
                t.result && t.result->stopped ? " (stopped)" : "");
    if (t.result) spreads_table(*t.result, view->summary);
    ImGui::BeginChild("##tolerance");
    const float line = ImGui::GetTextLineHeightWithSpacing();
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const ImVec2 size(avail.x, std::max(11.0f * line, avail.y));
    if (t.result) {
        chart_widget("##tolerance_chart", view->chart, size);
    } else {
        // While it runs: each realisation's efficiency in the order traced.
        plot::Series runs{.kind = plot::Series::Kind::Points,
                          .label = "efficiency so far",
                          .colour = plot::palette(0)};
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
            runs.x.push_back(double(i));
            runs.y.push_back(t.rows[i].efficiency);
        }
        chart_widget(
            "##tolerance_running",
            {.title = "Tolerance realisations running",
             .x = {"realisation", plot::Scale::Linear, 0.0, std::max(10.0, double(t.total))},
             .y = {"efficiency"},
             .series = {runs}},
            size);
    }
    ImGui::EndChild();
}

} // namespace fird::ui
