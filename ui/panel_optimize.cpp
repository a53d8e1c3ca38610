// The optimization panel: start, pause and stop any method of fird optimize; best l2
// against evaluations and each parameter's path, live; results saved as the command
// would save them.
#include <filesystem>

#include <fmt/format.h>
#include <imgui.h>

#include "panels.hpp"
#include "view_textures.hpp"

namespace fird::ui {

void start_search(Frame& f, SearchMethod method) {
    WorkbenchState& s = f.state;
    if (!s.editor.scene) return add_log(s, "error: open a scene before optimizing");
    if (s.editor.scene->reflector.optimize.empty() ||
        s.editor.scene->target.kind == TargetDesc::Kind::None)
        return add_log(s, "error: the scene needs [reflector.optimize] and a [target] to optimize");
    const std::string out = (std::filesystem::path("workbench_out") / "optimize").string();
    f.worker.submit(SearchJob{.scene = edited_scene(s), .method = method, .out_dir = out});
    add_log(s, fmt::format("optimize ({}) started; files in {}", method_name(method), out));
}

void optimize_panel(Frame& f) {
    WorkbenchState& s = f.state;
    ImGui::Begin("Optimization");
    const auto names = method_names();
    std::vector<const char*> items;
    for (const auto& n : names)
        items.push_back(n.c_str());
    ImGui::SetNextItemWidth(120);
    ImGui::Combo("method", &s.method, items.data(), int(items.size()));
    const SearchProgress p = f.worker.search();
    ImGui::SameLine();
    if (!p.running) {
        const bool can = s.editor.scene && !s.editor.scene->reflector.optimize.empty() &&
                         s.editor.scene->target.kind != TargetDesc::Kind::None;
        ImGui::BeginDisabled(!can);
        if (ImGui::Button("Start (O)"))
            start_search(f, *method_from_name(names[std::size_t(s.method)]));
        ImGui::EndDisabled();
    } else {
        if (ImGui::Button(p.paused ? "Resume" : "Pause")) f.worker.set_paused(!p.paused);
        ImGui::SameLine();
        if (ImGui::Button("Stop (Esc)")) f.worker.stop();
    }
    if (!p.history.empty()) {
        double best = HUGE_VAL;
        for (const Candidate& c : p.history)
            if (c.feasible && c.stage + 1 == p.stages.size()) best = std::min(best, c.l2_lm);
        ImGui::Text("%zu evaluations%s, best l2 %.5g lm (stage %s)", p.history.size(),
                    p.running ? "" : ", done", best,
                    p.stages.empty() ? "" : p.stages.back().name.c_str());
        if (p.result && p.result->final_l2_lm && p.result->noise_floor_l2_lm)
            ImGui::Text("final l2 %.5g lm, noise floor %.5g lm", *p.result->final_l2_lm,
                        *p.result->noise_floor_l2_lm);
        const ImVec2 avail = ImGui::GetContentRegionAvail();
        const auto w = std::uint32_t(std::max(200.0f, avail.x)),
                   h = std::uint32_t(std::max(200.0f, avail.y));
        update_search_plot(f.ctx, s, p, w, h);
        ImGui::Image(static_cast<ImTextureID>(s.search_plot.texture.get()),
                     ImVec2(float(w), float(h)));
    }
    ImGui::End();
}

} // namespace fird::ui
