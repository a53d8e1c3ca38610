// The scene panel: open a scene (path, recent scenes, drag and drop), a slider per
// parameter within its bounds, the trace settings, and the evaluation's figures.
#include <algorithm>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include "panels.hpp"

namespace fird::ui {

void request_trace(Frame& f) {
    WorkbenchState& s = f.state;
    if (!s.editor.scene) return;
    const Scene scene = edited_scene(s);
    const std::uint64_t full = s.editor.rays ? s.editor.rays : scene.trace.rays;
    std::vector<std::uint64_t> rays;
    if (s.editor.preview_rays < full) rays.push_back(s.editor.preview_rays);
    rays.push_back(full);
    f.worker.submit(TraceJob{.scene = *s.editor.scene,
                             .parameters = s.editor.parameters,
                             .rays = rays,
                             .pick = s.viewport.picked_ray});
    s.editor.dirty = false;
}

void scene_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::Scene);
    ImGui::InputTextWithHint("##path", "a scene (.toml) or a target (.ies, .ldt)", &s.editor.path);
    ImGui::SameLine();
    if (ImGui::Button("Open")) open_file(s, s.editor.path);
    if (!s.recent.empty() && ImGui::BeginCombo("recent", "recent scenes")) {
        for (const std::string& r : std::vector<std::string>(s.recent))
            if (ImGui::Selectable(r.c_str())) open_file(s, r);
        ImGui::EndCombo();
    }
    if (!s.editor.error.empty()) {
        // Wrapped, not cut: an error names its file and line.
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.9f, 0.2f, 0.2f, 1.0f));
        ImGui::TextWrapped("%s", s.editor.error.c_str());
        ImGui::PopStyleColor();
    }
    if (!s.editor.scene) {
        ImGui::TextWrapped("Open a scene file (or drop one on the window).");
        ImGui::End();
        return;
    }
    const Scene& scene = *s.editor.scene;
    ImGui::TextWrapped("%s: %s reflector", scene.name.c_str(), family_name(scene.reflector.family));
    ImGui::TextWrapped("target: %s", target_description(scene).c_str());
    ImGui::Separator();
    bool changed = false;
    for (auto& [name, value] : s.editor.parameters) {
        float v = float(value);
        const auto range = scene.reflector.optimize.find(name);
        const float lo = range != scene.reflector.optimize.end()
                             ? float(range->second.min)
                             : float(value - std::max(1.0, std::abs(value)));
        const float hi = range != scene.reflector.optimize.end()
                             ? float(range->second.max)
                             : float(value + std::max(1.0, std::abs(value)));
        if (ImGui::SliderFloat(name.c_str(), &v, lo, hi, "%.3f")) {
            value = v;
            changed = true;
        }
    }
    source_section(s);
    material_section(s);
    cad_section(s);
    int preview = int(s.editor.preview_rays);
    if (ImGui::InputInt("preview rays", &preview, 10000, 100000))
        s.editor.preview_rays = std::uint64_t(std::clamp(preview, 1000, 10000000));
    int rays = int(s.editor.rays ? s.editor.rays : scene.trace.rays);
    if (ImGui::InputInt("rays", &rays, 100000, 1000000))
        s.editor.rays = std::uint64_t(std::clamp(rays, 1000, 1000000000));
    if (changed) s.editor.dirty = true;
    if (ImGui::Button("Trace (T)") || s.editor.dirty) request_trace(f);
    if (f.snapshot) {
        const auto& t = f.snapshot->traced;
        ImGui::Separator();
        ImGui::TextWrapped("%s%llu rays: %llu effective, %llu reflected",
                           f.snapshot->preview ? "preview, " : "",
                           static_cast<unsigned long long>(t.tally.emitted),
                           static_cast<unsigned long long>(t.tally.emitted - t.tally.discarded),
                           static_cast<unsigned long long>(t.tally.farfield));
        ImGui::Text("far field %.2f lm of %.2f lm", f.snapshot->obtained_lm, scene.source.flux_lm);
        if (t.farfield.l2_lm)
            ImGui::Text("%s to the target %.5g %s", metric_name(scene.optimize.metric),
                        *t.farfield.l2_lm, metric_unit(scene.optimize.metric));
        // [reflector.constraints]: what the press can form, met or broken by this reflector.
        for (const ConstraintCheck& c : t.constraints) {
            ImGui::PushStyleColor(ImGuiCol_Text, c.met ? ImVec4(0.1f, 0.55f, 0.2f, 1.0f)
                                                       : ImVec4(0.9f, 0.2f, 0.2f, 1.0f));
            ImGui::TextWrapped("%s", fmt::format("{}: {:.4g} against {:g}, {}", c.name, c.value,
                                                 c.limit, c.met ? "met" : "broken")
                                         .c_str());
            ImGui::PopStyleColor();
        }
    }
    if (f.worker.busy()) ImGui::TextDisabled("working...");
    ImGui::End();
}

} // namespace fird::ui
