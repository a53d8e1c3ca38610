// The calibration panel: Table 1 and the semivariograms of fird calibrate, run beside
// the frames, with their plots and fitted curves.
#include <filesystem>

#include <fmt/format.h>
#include <imgui.h>

#include "panels.hpp"
#include "view_textures.hpp"

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

void calibrate_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::Calibrate);
    const char* kinds[] = {"rays (Table 1)", "semivariogram"};
    ImGui::SetNextItemWidth(160);
    ImGui::Combo("kind", &s.calibration_kind, kinds, 2);
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
    ImGui::SameLine();
    if (!c.running) {
        ImGui::BeginDisabled(!s.editor.scene ||
                             s.editor.scene->target.kind == TargetDesc::Kind::None);
        if (ImGui::Button("Start")) {
            const std::size_t k = std::size_t(s.calibration_parameter);
            start_calibration(f, s.calibration_kind == 0,
                              k > 0 && k < params.size() ? params[k] : "");
        }
        ImGui::EndDisabled();
    } else if (ImGui::Button("Stop")) {
        f.worker.stop();
    }
    if ((c.running || c.rays || c.semivariogram) && s.calibration_scene != s.editor.path) {
        // Another scene's calibration: not this scene's figures.
        ImGui::TextWrapped("the last calibration was of %s", s.calibration_scene.c_str());
    } else if (c.running || c.rays || c.semivariogram) {
        const ImVec2 avail = ImGui::GetContentRegionAvail();
        const auto w = std::uint32_t(std::max(200.0f, avail.x)),
                   h = std::uint32_t(std::max(200.0f, avail.y));
        update_calibration_plot(f.ctx, s, c, s.editor.scene ? s.editor.scene->name : "", w, h);
        ImGui::Image(static_cast<ImTextureID>(s.calibration_plot.texture.get()),
                     ImVec2(float(w), float(h)));
    }
    ImGui::End();
}

} // namespace fird::ui
