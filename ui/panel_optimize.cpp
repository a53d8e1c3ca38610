// The optimization panel: start, pause and stop any method of fird optimize; what the
// search is doing from its first second; best l2 against evaluations and each
// parameter's path, live; the best on the sliders when it ends (or on "apply best"), and
// "revert to start"; results saved as the command would save them.
#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include "chart_widget.hpp"
#include "model/design_parameters.hpp"
#include "optimize/search_report.hpp"
#include "panels.hpp"
#include "run_directory.hpp"

namespace fird::ui {

void start_search(Frame& f, SearchMethod method) {
    WorkbenchState& s = f.state;
    if (!s.editor.scene) return add_log(s, "error: open a scene before optimizing");
    if ((s.editor.scene->reflector.optimize.empty() && s.editor.scene->source_optimize.empty()) ||
        s.editor.scene->target.kind == TargetDesc::Kind::None)
        return add_log(s, "error: the scene needs [reflector.optimize] (or [source.optimize]) and "
                          "a [target] to optimize");
    const std::string out = new_run_folder(s, "optimize");
    if (out.empty()) return; // the error is in the log
    f.worker.submit(SearchJob{.scene = edited_scene(s), .method = method, .out_dir = out});
    s.search = {.scene_path = s.editor.path,
                .start = s.editor.parameters,
                .start_source = s.editor.scene->source,
                .running = true,
                .generation = f.worker.search().generation,
                .started_s = ImGui::GetTime()};
    add_log(s, fmt::format("optimize ({}) started; files in {}", method_name(method), out));
}

namespace {

// The best feasible candidate of the latest stage that has one (the search's own rule for
// its result: a later stage's l2 is at more rays, not comparable with an earlier one's).
const Candidate* best_candidate(const SearchProgress& p) {
    const Candidate* best = nullptr;
    for (const Candidate& c : p.history)
        if (c.feasible &&
            (!best || c.stage > best->stage || (c.stage == best->stage && c.score < best->score)))
            best = &c;
    return best;
}

std::map<std::string, double> best_parameters(const SearchProgress& p) {
    if (p.result && p.result->best) return p.result->best_parameters;
    std::map<std::string, double> named;
    if (const Candidate* c = best_candidate(p))
        for (std::size_t k = 0; k < p.names.size() && k < c->x.size(); ++k)
            named[p.names[k]] = c->x[k];
    return named;
}

// Parameters onto the sliders, traced (a preview, then the scene's rays).
void put_on_sliders(WorkbenchState& s, const std::map<std::string, double>& values) {
    std::map<std::string, double> source; // [source.optimize]'s: the source editor's
    for (const auto& [name, value] : values) {
        if (is_source_parameter(name))
            source[source_parameter_key(name)] = value;
        else if (auto it = s.editor.parameters.find(name); it != s.editor.parameters.end())
            it->second = value;
    }
    // Applied to the source the search started from (its tilts are relative to it); with
    // no source values (revert to start) that source itself.
    if (s.search.start_source && s.editor.scene && !s.editor.scene->source_optimize.empty())
        (void)set_source(s, source.empty() ? *s.search.start_source
                                           : moved_source(*s.search.start_source, source));
    s.editor.dirty = true;
}

std::string rays_text(std::uint64_t rays) {
    return fmt::format("{:.3g} rays", double(rays));
}

// What the search is doing, in words, from its first second.
void search_status(const WorkbenchState& s, const SearchProgress& p) {
    if (p.running) {
        const double elapsed = ImGui::GetTime() - s.search.started_s;
        if (p.history.empty()) {
            ImGui::TextWrapped("%s: %.0f s, preparing: tracing the desired far field and the "
                               "start reflector%s",
                               p.method.c_str(), elapsed, p.paused ? " (paused)" : "");
            return;
        }
        const StageSummary& stage = p.stages.back();
        ImGui::TextWrapped("%s: %.0f s, stage %zu %s at %s, %ux%u far field; %zu evaluations%s",
                           p.method.c_str(), elapsed, p.stages.size(), stage.name.c_str(),
                           rays_text(stage.fidelity.rays).c_str(), stage.fidelity.farfield_w,
                           stage.fidelity.farfield_h, p.history.size(),
                           p.paused ? " (paused)" : "");
    } else if (p.result) {
        const SearchResult& r = *p.result;
        const bool interrupted = r.stopped == StopReason::Interrupted;
        ImGui::TextWrapped("%s %s: %zu evaluations in %.0f s%s", r.method.c_str(),
                           interrupted ? "interrupted" : "done", r.history.size(), r.time_s,
                           interrupted ? " (the best so far is on the sliders)"
                                       : fmt::format(" ({})", stop_reason_name(r.stopped)).c_str());
        if (r.start_l2_lm && r.final_l2_lm)
            ImGui::TextWrapped(
                "%s",
                fmt::format("{} at the scene's rays: start {:.5g} {}, best {:.5g} {}{}", r.metric,
                            *r.start_l2_lm, r.metric_unit, *r.final_l2_lm, r.metric_unit,
                            r.noise_floor_l2_lm ? fmt::format(" (noise floor {:.3g} {})",
                                                              *r.noise_floor_l2_lm, r.metric_unit)
                                                : "")
                    .c_str());
        if (!p.out_dir.empty()) ImGui::TextWrapped("files in %s", p.out_dir.c_str());
    }
    if (const Candidate* c = best_candidate(p); c && c->stage < p.stages.size()) {
        const Fidelity& fid = p.stages[c->stage].fidelity;
        const FarFieldMetric metric =
            s.editor.scene ? s.editor.scene->optimize.metric : FarFieldMetric::L2;
        ImGui::TextWrapped("best so far: %s %.5g %s at %s (%ux%u far field, stage %s)",
                           metric_name(metric), c->l2_lm, metric_unit(metric),
                           rays_text(fid.rays).c_str(), fid.farfield_w, fid.farfield_h,
                           p.stages[c->stage].name.c_str());
        // The penalty the search added ([optimize] smoothness), beside the l2: the
        // candidate's own score less its l2 (the weight it was searched with).
        if (c->score > c->l2_lm)
            ImGui::TextWrapped("%s",
                               fmt::format("smoothness: bending energy {:.4g}, penalty "
                                           "{:.4g} {}",
                                           c->smoothness, c->score - c->l2_lm, metric_unit(metric))
                                   .c_str());
    }
}

// The search so far as a result (what progress.png draws from).
SearchResult progress_result(const SearchProgress& p) {
    SearchResult r = p.result.value_or(SearchResult{});
    r.method = p.method;
    r.names = p.names;
    r.bounds = p.bounds;
    r.history = p.history;
    r.stages = p.stages;
    return r;
}

// The progress charts at the panel's size: l2 on top, the parameters in a grid whose
// columns follow the width; below their least heights the panel scrolls instead of
// squeezing them.
void progress_plots(const SearchProgress& p) {
    ProgressCharts charts = progress_charts(progress_result(p));
    // Rows a small panel can spare: no title (the status above names the method), the
    // stages by name and rays (the status names their grids), one line for the y axis.
    charts.l2.title.clear();
    // The score plotted: the l2, or with a smoothness weight the l2 plus its penalty.
    const bool weighted = std::any_of(p.history.begin(), p.history.end(), [](const Candidate& c) {
        return c.feasible && c.score > c.l2_lm;
    });
    charts.l2.y.label = weighted ? "score (l2 + smoothness penalty) of each reflector tested"
                                 : "l2 of each reflector tested";
    for (std::size_t k = 0; k < p.stages.size() && 2 * k < charts.l2.series.size(); ++k)
        charts.l2.series[2 * k].label =
            fmt::format("{} {:.0e}", p.stages[k].name, double(p.stages[k].fidelity.rays));
    ImGui::BeginChild("##progress");
    const float line = ImGui::GetTextLineHeightWithSpacing();
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const std::size_t n = charts.parameters.size();
    const int columns = std::clamp(int(avail.x / (16.0f * line)), 1, std::max(1, int(n)));
    const int rows = int((n + std::size_t(columns) - 1) / std::size_t(columns));
    const float l2_h = std::max(10.0f * line, 0.45f * avail.y);
    const float spacing = ImGui::GetStyle().ItemSpacing.y;
    const float param_h =
        rows ? std::max(8.0f * line, (avail.y - l2_h) / float(rows) - spacing) : 0.0f;
    chart_widget("##l2", charts.l2, ImVec2(avail.x, l2_h));
    const float col_w =
        (avail.x - ImGui::GetStyle().ItemSpacing.x * float(columns - 1)) / float(columns);
    for (std::size_t k = 0; k < n; ++k) {
        // The evaluations' label under the bottom row only (it is the same for all).
        if (int(k) / columns < rows - 1) charts.parameters[k].x.label.clear();
        if (k % std::size_t(columns) != 0) ImGui::SameLine();
        chart_widget(fmt::format("##p{}", k).c_str(), charts.parameters[k], ImVec2(col_w, param_h));
    }
    ImGui::EndChild();
}

} // namespace

void optimize_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::Optimize);
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
    // (A search still queued behind a trace has not touched the generation yet.)
    // Results are the searched scene's: another scene opened since shows none of them
    // (nor takes its parameters).
    const bool this_scene = s.search.scene_path == s.editor.path;
    if (s.search.running && !p.running && p.generation > s.search.generation) {
        // The search ended: its best goes to the sliders. The worker has already shown
        // it at the scene's rays, so the sliders follow without a new trace.
        s.search.running = false;
        if (p.result && p.result->best && this_scene)
            for (const auto& [name, value] : p.result->best_parameters)
                s.editor.parameters[name] = value;
    }
    ImGui::TextUnformatted("runs under");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-FLT_MIN);
    ImGui::InputTextWithHint("##runs", runs_directory().c_str(), &s.runs_dir);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("each search writes a new folder under this one (never overwriting)");
    if (!this_scene && (p.running || p.result)) {
        ImGui::TextWrapped("the last search was of %s", s.search.scene_path.c_str());
        ImGui::End();
        return;
    }
    search_status(s, p);
    if (!p.history.empty() || p.result) {
        ImGui::BeginDisabled(!best_candidate(p));
        if (ImGui::Button("apply best")) put_on_sliders(s, best_parameters(p));
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::BeginDisabled(s.search.start.empty());
        if (ImGui::Button("revert to start")) put_on_sliders(s, s.search.start);
        ImGui::EndDisabled();
    }
    if (!p.history.empty()) progress_plots(p);
    ImGui::End();
}

} // namespace fird::ui
