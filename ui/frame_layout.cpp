// The frame: the menu bar, the panels tiled from the layout (ui/layout.hpp) with the
// splitters the user drags between them, and the keyboard shortcuts. Panels are windows
// placed and sized every frame (Dear ImGui 1.86 has no docking): none can be moved by its
// title bar, and none can overlap another or leave the window.
#include <algorithm>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>

#include "panels.hpp"

namespace fird::ui {

namespace {

constexpr ImGuiWindowFlags kPanelFlags =
    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
    ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;

LayoutMetrics metrics() {
    // Sizes in pixels at the UI's scale (HiDPI scales the font and the style).
    const float scale = ImGui::GetIO().FontGlobalScale;
    LayoutMetrics m;
    m.gap_px *= scale;
    m.min_panel_w *= scale;
    m.min_panel_h *= scale;
    return m;
}

// Returns the menu bar's height.
float menu_bar(Frame& f) {
    float height = 0.0f;
    if (!ImGui::BeginMainMenuBar()) return height;
    height = ImGui::GetWindowSize().y;
    if (ImGui::BeginMenu("View")) {
        if (ImGui::MenuItem("Frame all", "F")) f.state.viewport.frame_all = true;
        if (ImGui::MenuItem("Reset view", "Home")) f.state.viewport.camera_set = false;
        ImGui::Separator();
        if (ImGui::MenuItem("Reset layout")) f.state.layout = Layout{};
        ImGui::EndMenu();
    }
    if (ImGui::MenuItem("Help", "F1")) f.state.show_help = !f.state.show_help;
    ImGui::EndMainMenuBar();
    return height;
}

// The splitters, as invisible buttons in the gaps between the panels, on a window behind
// them that covers the panels' area (the gaps are the only part of it not covered).
void splitters(Frame& f, const PanelRect& area, const LayoutMetrics& m) {
    ImGui::SetNextWindowPos(ImVec2(area.x, area.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(area.w, area.h), ImGuiCond_Always);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::Begin("##layout", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus |
                     ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoBackground |
                     ImGuiWindowFlags_NoScrollWithMouse);
    ImGui::PopStyleVar();
    const ImGuiIO& io = ImGui::GetIO();
    for (const Splitter s : {Splitter::Left, Splitter::Right, Splitter::Row}) {
        const PanelRect r = splitter_rect(f.state.layout, s, area, m);
        if (r.w <= 0 || r.h <= 0) continue;
        ImGui::SetCursorScreenPos(ImVec2(r.x, r.y));
        ImGui::PushID(int(s));
        ImGui::InvisibleButton("##splitter", ImVec2(r.w, r.h));
        ImGui::PopID();
        const bool columns = s != Splitter::Row;
        if (ImGui::IsItemHovered() || ImGui::IsItemActive()) {
            ImGui::SetMouseCursor(columns ? ImGuiMouseCursor_ResizeEW : ImGuiMouseCursor_ResizeNS);
            ImGui::GetWindowDrawList()->AddRectFilled(
                ImVec2(r.x, r.y), ImVec2(r.x + r.w, r.y + r.h),
                ImGui::GetColorU32(ImGuiCol_SeparatorHovered));
        }
        if (ImGui::IsItemActive()) {
            const float delta = columns ? io.MouseDelta.x : io.MouseDelta.y;
            if (delta != 0.0f) f.state.layout = drag_splitter(f.state.layout, s, delta, area, m);
        }
    }
    ImGui::End();
}

void shortcuts(Frame& f) {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return;
    // Dear ImGui 1.86 indexes keys by the backend's codes: GLFW's.
    if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) f.state.show_help = !f.state.show_help;
    if (ImGui::IsKeyPressed(GLFW_KEY_T, false)) request_trace(f);
    if (ImGui::IsKeyPressed(GLFW_KEY_O, false) && !f.worker.search().running)
        start_search(f, *method_from_name(method_names()[std::size_t(f.state.method)]));
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) f.worker.stop();
    if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) f.worker.set_paused(!f.worker.search().paused);
    if (ImGui::IsKeyPressed(GLFW_KEY_F, false)) f.state.viewport.frame_all = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) f.state.viewport.camera_set = false;
    if (io.KeyCtrl && ImGui::IsKeyPressed(GLFW_KEY_Q, false)) f.state.quit = true;
}

} // namespace

void begin_panel(Frame& f, PanelId id) {
    const PanelRect r = f.state.panels[std::size_t(id)];
    const LayoutMetrics m = metrics();
    ImGui::SetNextWindowPos(ImVec2(r.x, r.y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(r.w, r.h), ImGuiCond_Always);
    ImGuiWindowFlags flags = kPanelFlags;
    if (r.w < m.min_panel_w) {
        // Narrower than its minimum: the content keeps the minimum width and scrolls.
        ImGui::SetNextWindowContentSize(
            ImVec2(m.min_panel_w - 2.0f * ImGui::GetStyle().WindowPadding.x, 0.0f));
        flags |= ImGuiWindowFlags_HorizontalScrollbar;
    }
    ImGui::Begin(panel_title(id), nullptr, flags);
    const ImVec2 at = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    f.state.drawn[std::size_t(id)] = {at.x, at.y, size.x, size.y};
}

void build_frame(Frame& f) {
    const ImGuiIO& io = ImGui::GetIO();
    f.state.display_w = io.DisplaySize.x, f.state.display_h = io.DisplaySize.y;
    shortcuts(f);
    const float top = menu_bar(f);
    const PanelRect area{0.0f, top, io.DisplaySize.x, std::max(0.0f, io.DisplaySize.y - top)};
    const LayoutMetrics m = metrics();
    f.state.panels = tile(f.state.layout, area, m);
    (void)poll_cad_export(f.state);
    scene_panel(f);
    viewport_panel(f);
    farfield_panel(f);
    log_panel(f);
    optimize_panel(f);
    calibrate_panel(f);
    // After the panels: Dear ImGui puts a window that never comes to the front behind
    // those that exist when it is created, and the splitters' window must be the backmost.
    splitters(f, area, m);
    help_panel(f);
}

} // namespace fird::ui
