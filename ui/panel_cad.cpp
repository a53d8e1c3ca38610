// The scene panel's CAD section: the reflector shown (the sliders' values) written as
// reflector.step and reflector.stl with fird export --cad's options and report
// (export/cad_export.hpp), on a thread of its own, so that frames go on while OpenCASCADE
// fits, trims, bends and thickens.
#include <filesystem>
#include <future>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include "export/cad_option_error.hpp"
#include "export/export_modules.hpp"
#include "model/surface.hpp"
#include "panels.hpp"

namespace fird::ui {

namespace {

// One line of what was written: the surface, the sheet's bends, the files.
std::string cad_summary(const CadReport& r, const std::string& dir) {
    std::string line = fmt::format(
        "CAD: {} files in {}: {}, largest deviation {:.2g} mm", r.files.size(), dir,
        r.revolved ? "the profile revolved, exact"
        : r.exact  ? "the family's B-spline, exact"
                   : fmt::format("B-spline fitted to {} x {} heights", r.fit_nx, r.fit_ny),
        r.max_deviation_mm);
    if (r.creased) line += ", creased at the holder";
    if (r.bend)
        line += fmt::format("; sheet bent with {:g} mm, the bends {:.3g} mm off the family",
                            r.bend->radius_mm, r.bend->max_deviation_mm);
    return line;
}

} // namespace

bool start_cad_export(WorkbenchState& s) {
    CadExportForm& c = s.cad;
    if (!s.editor.scene) {
        c.error = "no scene is open";
        return false;
    }
    if (c.writing.valid()) {
        c.error = "a CAD export is being written";
        return false;
    }
    // The surface is made here, and the CAD module loaded (once, ~60 ms), so that a parameter
    // the family refuses or a missing module is this frame's error (before a run folder is
    // made for it); the thread gets its own copy of the surface.
    const Scene scene = edited_scene(s);
    std::string dir;
    try {
        auto surface =
            std::make_shared<const Surface>(Surface::make(scene.reflector, scene.holder));
        const auto export_cad = cad_exports().cad;
        dir = c.dir.empty() ? new_run_folder(s, "cad") : c.dir;
        if (dir.empty()) {
            c.error = s.log.empty() ? "no run folder" : s.log.back();
            return false;
        }
        const CadOptions options{.tolerance_mm = c.tolerance_mm,
                                 .thickness_mm = c.thickness_mm,
                                 .bend_radius_mm = c.bend_radius_mm};
        c.writing = std::async(std::launch::async, [export_cad, surface, options, dir] {
            return export_cad(*surface, options, dir);
        });
    } catch (const std::exception& e) {
        c.error = e.what();
        add_log(s, "error: CAD: " + c.error);
        return false;
    }
    c.writing_dir = dir;
    c.error.clear();
    return true;
}

bool poll_cad_export(WorkbenchState& s) {
    CadExportForm& c = s.cad;
    if (!c.writing.valid()) return false;
    if (c.writing.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return true;
    try {
        c.report = c.writing.get();
        c.written_dir = c.writing_dir;
        add_log(s, cad_summary(*c.report, c.written_dir));
    } catch (const std::exception& e) {
        // As the command's one line: the option it names, or the file it could not write.
        c.report.reset();
        c.error = e.what();
        add_log(s, "error: CAD: " + c.error);
    }
    return false;
}

void cad_section(WorkbenchState& s) {
    CadExportForm& c = s.cad;
    // Open once there is something to show (an export a script started, say).
    if (c.writing.valid() || c.report || !c.error.empty())
        ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (!ImGui::CollapsingHeader("CAD: STEP and STL")) return;
    ImGui::InputTextWithHint("folder", "a new run folder", &c.dir);
    ImGui::InputDouble("tolerance (mm)", &c.tolerance_mm, 0.0, 0.0, "%.4g");
    ImGui::InputDouble("sheet (mm)", &c.thickness_mm, 0.0, 0.0, "%.3g");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("0: the surface alone; else a solid sheet this thick");
    ImGui::InputDouble("bend radius (mm)", &c.bend_radius_mm, 0.0, 0.0, "%.3g");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("where the holder clamps the reflector, its sheet's creases are bent "
                          "to this radius (0: twice the sheet)");
    const bool busy = c.writing.valid();
    ImGui::BeginDisabled(busy || !s.editor.scene);
    if (ImGui::Button(busy ? "writing..." : "Write reflector.step, .stl")) start_cad_export(s);
    ImGui::EndDisabled();
    if (!c.error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.9f, 0.2f, 0.2f, 1.0f));
        ImGui::TextWrapped("%s", c.error.c_str());
        ImGui::PopStyleColor();
    } else if (c.report) {
        ImGui::TextWrapped("%s", cad_summary(*c.report, c.written_dir).c_str());
    }
}

} // namespace fird::ui
