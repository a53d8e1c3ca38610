// The log and the help panel (keyboard shortcuts).
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "panels.hpp"

namespace fird::ui {

void log_panel(Frame& f) {
    ImGui::Begin("Log");
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
    ImGui::Begin("Help", &f.state.show_help);
    ImGui::TextUnformatted("F1        this help\n"
                           "T         trace the scene again\n"
                           "O         start the optimization (the Optimization panel's method)\n"
                           "Esc       stop the running search or calibration\n"
                           "Space     pause / resume the search\n"
                           "Ctrl+Q    quit\n\n"
                           "Viewport: left drag orbits, right drag pans, the wheel zooms,\n"
                           "a click picks a ray (its RQRM walk: < and > step through it).\n"
                           "Drop a scene (.toml) on the window to open it, or an IES / LDT\n"
                           "file to make it the scene's desired far field.");
    ImGui::End();
}

void build_frame(Frame& f) {
    const ImGuiIO& io = ImGui::GetIO();
    const float W = io.DisplaySize.x, H = io.DisplaySize.y;
    const auto place = [&](float x, float y, float w, float h) {
        ImGui::SetNextWindowPos(ImVec2(x * W, y * H), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(w * W, h * H), ImGuiCond_FirstUseEver);
    };
    // Dear ImGui 1.86 indexes keys by the backend's codes: GLFW's.
    if (!io.WantTextInput) {
        if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) f.state.show_help = !f.state.show_help;
        if (ImGui::IsKeyPressed(GLFW_KEY_T, false)) request_trace(f);
        if (ImGui::IsKeyPressed(GLFW_KEY_O, false) && !f.worker.search().running)
            start_search(f, *method_from_name(method_names()[std::size_t(f.state.method)]));
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) f.worker.stop();
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false))
            f.worker.set_paused(!f.worker.search().paused);
        if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Q, false)) f.state.quit = true;
    }
    place(0.0f, 0.0f, 0.24f, 0.62f);
    scene_panel(f);
    place(0.24f, 0.0f, 0.40f, 0.62f);
    viewport_panel(f);
    place(0.64f, 0.0f, 0.36f, 0.62f);
    farfield_panel(f);
    place(0.0f, 0.62f, 0.24f, 0.38f);
    log_panel(f);
    place(0.24f, 0.62f, 0.40f, 0.38f);
    optimize_panel(f);
    place(0.64f, 0.62f, 0.36f, 0.38f);
    calibrate_panel(f);
    place(0.3f, 0.2f, 0.4f, 0.4f);
    help_panel(f);
}

} // namespace fird::ui
