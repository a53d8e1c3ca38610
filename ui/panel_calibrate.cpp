// The calibration panel: Table 1 and the semivariograms of fird calibrate, run beside
// the frames, with their plots and fitted curves; and fird tolerance's realisations
// (panel_tolerance.cpp).
#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <imgui.h>

#include "calibrate/calibration_report.hpp"
#include "chart_widget.hpp"
#include "panels.hpp"

namespace fird::ui {

void start_calibration(Frame& f, bool rays_table, const std::string& parameter) {
    WorkbenchState& s = f.state;
    if (!s.editor.scene || s.editor.scene->target.kind == TargetDesc::Kind::None)
        return add_log(s, "error: calibration needs a scene with a [target]");
    if (!parameter.empty() && !s.editor.scene->reflector.optimize.count(parameter))
        return add_log(s, "error: " + parameter + " is not in [reflector.optimize]");
    const std::string out = new_run_folder(s, "calibrate");
    if (out.empty()) return; // the error is in the log
    f.worker.submit(CalibrateJob{.scene = edited_scene(s),
                                 .rays_table = rays_table,
                                 .parameter = parameter,
                                 .out_dir = out});
    s.calibration_scene = s.editor.path;
    add_log(s, "calibration started; files in " + out);
}

namespace {

// The calibration's charts at the panel's size: Table 1's rays, or one semivariogram per
// parameter (in a grid whose columns follow the width, scrolling below their least
// height), or the runs' l2 while it runs.
void calibration_plots(const CalibrationProgress& c, const std::string& scene) {
    ImGui::BeginChild("##calibration");
    const float line = ImGui::GetTextLineHeightWithSpacing();
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    if (c.rays) {
        chart_widget("##rays", rays_table_chart(*c.rays, scene),
                     ImVec2(avail.x, std::max(13.0f * line, avail.y)));
    } else if (c.semivariogram && !c.semivariogram->parameters.empty()) {
        const auto& ps = c.semivariogram->parameters;
        const int columns = std::clamp(int(avail.x / (20.0f * line)), 1, int(ps.size()));
        const int rows = int((ps.size() + std::size_t(columns) - 1) / std::size_t(columns));
        const float h =
            std::max(11.0f * line, avail.y / float(rows) - ImGui::GetStyle().ItemSpacing.y);
        const float w =
            (avail.x - ImGui::GetStyle().ItemSpacing.x * float(columns - 1)) / float(columns);
        for (std::size_t k = 0; k < ps.size(); ++k) {
            if (k % std::size_t(columns) != 0) ImGui::SameLine();
            chart_widget(
                fmt::format("##semivariogram{}", k).c_str(),
                semivariogram_chart(ps[k], c.semivariogram->rays, scene, c.semivariogram->metric),
                ImVec2(w, h));
        }
    } else {
        plot::Series runs{
            .kind = plot::Series::Kind::Points, .label = "l2 so far", .colour = plot::palette(0)};
        for (std::size_t i = 0; i < c.partial.size(); ++i) {
            runs.x.push_back(double(i));
            runs.y.push_back(c.partial[i]);
        }
        chart_widget("##running",
                     {.title = "Calibration running",
                      .x = {"run or point", plot::Scale::Linear, 0.0,
                            std::max(10.0, double(c.partial.size()))},
                      .y = {"l2 (lm)"},
                      .series = {runs}},
                     ImVec2(avail.x, std::max(11.0f * line, avail.y)));
    }
    ImGui::EndChild();
}

} // namespace

void calibrate_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::Calibrate);
    const char* kinds[] = {"rays (Table 1)", "semivariogram", "tolerance"};
    ImGui::SetNextItemWidth(160);
    ImGui::Combo("kind", &s.calibration_kind, kinds, 3);
    const bool tolerance = s.calibration_kind == 2;
    std::vector<std::string> params{"all"};
    if (s.editor.scene)
        for (const auto& [k, range] : s.editor.scene->reflector.optimize)
            params.push_back(k);
    if (s.calibration_kind == 1) {
        std::vector<const char*> items;
        for (const auto& p : params)
            items.push_back(p.c_str());
        ImGui::SameLine();
        ImGui::SetNextItemWidth(100);
        ImGui::Combo("parameter", &s.calibration_parameter, items.data(), int(items.size()));
    }
    const CalibrationProgress c = f.worker.calibration();
    const bool tolerance_running = f.worker.tolerance_pending();
    ImGui::SameLine();
    if (!c.running && !tolerance_running) {
        // A calibration compares with the target; tolerances rank by efficiency without one.
        ImGui::BeginDisabled(tolerance ? !tolerance_can_start(s)
                                       : !s.editor.scene ||
                                             s.editor.scene->target.kind == TargetDesc::Kind::None);
        if (ImGui::Button("Start")) {
            const std::size_t k = std::size_t(s.calibration_parameter);
            if (tolerance)
                start_tolerance(f);
            else
                start_calibration(f, s.calibration_kind == 0,
                                  k > 0 && k < params.size() ? params[k] : "");
        }
        ImGui::EndDisabled();
    } else if (ImGui::Button("Stop")) {
        f.worker.stop();
    }
    if (tolerance) {
        tolerance_section(f);
    } else if ((c.running || c.rays || c.semivariogram) && s.calibration_scene != s.editor.path) {
        // Another scene's calibration: not this scene's figures.
        ImGui::TextWrapped("the last calibration was of %s", s.calibration_scene.c_str());
    } else if (c.running || c.rays || c.semivariogram) {
        calibration_plots(c, s.editor.scene ? s.editor.scene->name : "");
    }
    ImGui::End();
}

} // namespace fird::ui
