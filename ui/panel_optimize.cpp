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
#include "folder_follow.hpp"
#include "io/scene_file.hpp"
#include "model/design_parameters.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search_report.hpp"
#include "optimize/search_start.hpp"
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
    if (s.tailored_start)
        if (const auto why = tailored_start_refusal(*s.editor.scene))
            return add_log(s, "error: tailored start: " + *why);
    const std::string out = new_run_folder(s, "optimize");
    if (out.empty()) return; // the error is in the log
    f.worker.submit(SearchJob{.scene = edited_scene(s),
                              .method = method,
                              .out_dir = out,
                              .tailored_start = s.tailored_start});
    s.search = {.scene_path = s.editor.path,
                .start = s.editor.parameters,
                .start_source = s.editor.scene->source,
                .running = true,
                .generation = f.worker.search().generation,
                .started_s = ImGui::GetTime()};
    add_log(s, fmt::format("optimize ({}{}) started; files in {}", method_name(method),
                           s.tailored_start ? ", tailored start" : "", out));
}

namespace {

std::map<std::string, double> best_parameters(const SearchProgress& p) {
    if (p.result && p.result->best) return p.result->best_parameters;
    std::map<std::string, double> named;
    if (const Candidate* c = latest_stage_best(p.history))
        for (std::size_t k = 0; k < p.names.size() && k < c->x.size(); ++k)
            named[p.names[k]] = c->x[k];
    return named;
}

// Parameters onto the sliders, traced (a preview, then the scene's rays); [source.optimize]'s
// values are applied to the source the search started from.
void put_on_sliders(WorkbenchState& s, const std::map<std::string, double>& values,
                    const std::optional<SourceDesc>& start_source) {
    std::map<std::string, double> source; // [source.optimize]'s: the source editor's
    for (const auto& [name, value] : values) {
        if (is_source_parameter(name))
            source[source_parameter_key(name)] = value;
        else if (auto it = s.editor.parameters.find(name); it != s.editor.parameters.end())
            it->second = value;
    }
    // Applied to the source the search started from (its tilts are relative to it); with
    // no source values (revert to start) that source itself.
    if (start_source && s.editor.scene && !s.editor.scene->source_optimize.empty())
        (void)set_source(s, source.empty() ? *start_source : moved_source(*start_source, source));
    s.editor.dirty = true;
}

std::string rays_text(std::uint64_t rays) {
    return fmt::format("{:.3g} rays", double(rays));
}

// What the search is doing, in words, from its first second (`elapsed_s`: since it began,
// where that is known).
void search_status(const SearchProgress& p, std::optional<double> elapsed_s,
                   FarFieldMetric metric) {
    if (p.running) {
        const std::string method =
            elapsed_s ? fmt::format("{}: {:.0f} s", p.method, *elapsed_s) : p.method;
        if (p.history.empty()) {
            ImGui::TextWrapped("%s, preparing: tracing the desired far field and the "
                               "start reflector%s",
                               method.c_str(), p.paused ? " (paused)" : "");
            return;
        }
        const StageSummary& stage = p.stages.back();
        ImGui::TextWrapped("%s, stage %zu %s at %s, %ux%u far field; %zu evaluations%s",
                           method.c_str(), p.stages.size(), stage.name.c_str(),
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
        if (r.population) ImGui::TextWrapped("%s", population_summary(*r.population).c_str());
        if (r.levenberg) ImGui::TextWrapped("%s", levenberg_summary(*r.levenberg).c_str());
        if (!p.out_dir.empty()) ImGui::TextWrapped("files in %s", p.out_dir.c_str());
    }
    if (const Candidate* c = latest_stage_best(p.history); c && c->stage < p.stages.size()) {
        const Fidelity& fid = p.stages[c->stage].fidelity;
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

// Whether the open scene (as edited) is the one `search` searches: the same scene but for
// the values searched (its best can go on the sliders, inside the same boxes).
bool searches_open_scene(const WorkbenchState& s, const FollowedSearch& search) {
    if (!s.editor.scene || search.names.empty()) return false;
    const ParameterSpace space = parameter_space(search.scene);
    if (parameter_space(*s.editor.scene).names != space.names) return false;
    // Both with the same values for what is searched, written as their files would be.
    const auto text = [&](const Scene& scene) {
        return scene_to_toml(with_absolute_files(space.candidate(scene, space.start)));
    };
    return text(search.scene) == text(edited_scene(s));
}

// A search followed from its folder, drawn as the worker's own: its status, its best to the
// sliders when the open scene is the one it searches, its charts.
void followed_search(WorkbenchState& s) {
    const FolderFollow& follow = s.follow;
    ImGui::TextWrapped("following %s", follow.dir.c_str());
    if (!follow.error.empty())
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", follow.error.c_str());
    if (!follow.search) {
        ImGui::TextWrapped("waiting for its search to begin (no options.json there yet)");
        return;
    }
    const FollowedSearch& search = *follow.search;
    const SearchProgress p = followed_progress(search);
    ImGui::TextWrapped("%s", fmt::format("{}: {} of {}", search.scene.name, p.method,
                                         fmt::join(search.names, ", "))
                                 .c_str());
    search_status(p, std::nullopt, search.scene.optimize.metric);
    const bool same = searches_open_scene(s, search);
    ImGui::BeginDisabled(!latest_stage_best(p.history) || !same);
    if (ImGui::Button("apply best")) apply_followed_best(s); // enabled only where it can
    ImGui::EndDisabled();
    if (!same && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("open the scene it searches first, as it searches it (a job folder's "
                          "scene.toml)");
    if (follow.scene_toml) {
        ImGui::SameLine();
        if (ImGui::Button("open its scene"))
            (void)open_file(s, (std::filesystem::path(follow.dir) / "scene.toml").string());
    }
    if (!p.history.empty()) progress_plots(p);
}

} // namespace

void apply_followed_best(WorkbenchState& s) {
    if (!s.follow.search) throw std::runtime_error("no followed search has begun");
    const FollowedSearch& search = *s.follow.search;
    if (!searches_open_scene(s, search))
        throw std::runtime_error(
            fmt::format("the open scene is not the one {} searches", s.follow.dir));
    const SearchProgress p = followed_progress(search);
    if (!latest_stage_best(p.history))
        throw std::runtime_error("the followed search has no best yet");
    put_on_sliders(s, best_parameters(p), search.scene.source);
    add_log(s, fmt::format("the best of {} on the sliders", s.follow.dir));
}

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
    // A tailored start where the scene's family takes one (the profile's free heights).
    const auto refusal = s.editor.scene ? tailored_start_refusal(*s.editor.scene)
                                        : std::optional<std::string>("no scene is open");
    if (refusal) s.tailored_start = false;
    ImGui::BeginDisabled(refusal.has_value() || p.running);
    ImGui::Checkbox("tailored start", &s.tailored_start);
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("%s", refusal ? refusal->c_str()
                                        : "begin at the profile that makes the target from the "
                                          "source's centre (flux mapping), not at the scene's");
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
    poll_followed_folder(s.follow, ImGui::GetTime());
    cluster_section(f);
    if (!s.follow.dir.empty()) {
        followed_search(s);
        ImGui::End();
        return;
    }
    if (!this_scene && (p.running || p.result)) {
        ImGui::TextWrapped("the last search was of %s", s.search.scene_path.c_str());
        ImGui::End();
        return;
    }
    search_status(p, ImGui::GetTime() - s.search.started_s,
                  s.editor.scene ? s.editor.scene->optimize.metric : FarFieldMetric::L2);
    if (!p.history.empty() || p.result) {
        ImGui::BeginDisabled(!latest_stage_best(p.history));
        if (ImGui::Button("apply best"))
            put_on_sliders(s, best_parameters(p), s.search.start_source);
        ImGui::EndDisabled();
        ImGui::SameLine();
        ImGui::BeginDisabled(s.search.start.empty());
        if (ImGui::Button("revert to start"))
            put_on_sliders(s, s.search.start, s.search.start_source);
        ImGui::EndDisabled();
    }
    if (!p.history.empty()) progress_plots(p);
    ImGui::End();
}

} // namespace fird::ui
