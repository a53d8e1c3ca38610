// The log and the help panel (keyboard shortcuts and mouse).
#include <imgui.h>

#include "panels.hpp"

namespace fird::ui {

void log_panel(Frame& f) {
    begin_panel(f, PanelId::Log);
    for (const std::string& line : f.state.log) {
        const bool error = line.rfind("error:", 0) == 0;
        if (error) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.9f, 0.25f, 0.2f, 1.0f));
        ImGui::TextWrapped("%s", line.c_str());
        if (error) ImGui::PopStyleColor();
    }
    if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY()) ImGui::SetScrollHereY(1.0f);
    ImGui::End();
}

void help_panel(Frame& f) {
    if (!f.state.show_help) return;
    // Over the panels, in the middle of the window, closed with its [x] or F1.
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f),
                            ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::Begin("Help", &f.state.show_help,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse);
    ImGui::TextUnformatted("F1        this help\n"
                           "T         trace the scene again\n"
                           "O         start the optimization (the Optimization panel's method)\n"
                           "Esc       stop the running search or calibration\n"
                           "Space     pause / resume the search\n"
                           "F         frame all (the holder fills the viewport)\n"
                           "Home      reset the view\n"
                           "Ctrl+Q    quit\n\n"
                           "Viewport: left drag orbits, right drag pans, the wheel zooms,\n"
                           "a double click frames all, a click picks a ray (its RQRM\n"
                           "walk: < and > step through it).\n"
                           "Far field: the wheel zooms, a double click shows it whole.\n"
                           "Drag the gaps between panels to resize them;\n"
                           "View > Reset layout restores the default.\n"
                           "Drop a scene (.toml) on the window to open it, an IES / LDT\n"
                           "file to make it the scene's desired far field, or a ray file\n"
                           "(.tm25ray, .npy, .csv) to make it the scene's source.");
    ImGui::End();
}

} // namespace fird::ui
