// The optimize panel's section for other machines (issue 28): the search shown handed to a
// cluster as a job folder (scene.toml, run.sh for mpirun, slurm.sh for sbatch) and any
// search's folder followed live from its files, here or on a file system the cluster shares.
#include <algorithm>
#include <utility>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include "folder_follow.hpp"
#include "io/program_files.hpp"
#include "panels.hpp"

namespace fird::ui {

namespace {

// A command to copy: shown whole in a read-only field (selectable), with a copy button.
void command_line(const char* id, const std::string& command) {
    ImGui::PushID(id);
    if (ImGui::SmallButton("copy")) ImGui::SetClipboardText(command.c_str());
    ImGui::SameLine();
    std::string shown = command;
    ImGui::SetNextItemWidth(-FLT_MIN);
    ImGui::InputText("##command", &shown, ImGuiInputTextFlags_ReadOnly);
    ImGui::PopID();
}

void count_field(const char* label, std::uint32_t& value, const char* tip) {
    int v = int(value);
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6);
    if (ImGui::InputInt(label, &v)) value = std::uint32_t(std::clamp(v, 1, 1 << 20));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tip);
}

} // namespace

bool write_job(Frame& f) {
    WorkbenchState& s = f.state;
    if (!s.editor.scene) {
        add_log(s, "error: open a scene before writing a job");
        return false;
    }
    if (s.editor.scene->reflector.optimize.empty() && s.editor.scene->source_optimize.empty()) {
        add_log(s, "error: the scene needs [reflector.optimize] (or [source.optimize]) for a job");
        return false;
    }
    if (const auto why = cluster_shape_error(s.cluster.shape)) {
        add_log(s, "error: " + *why);
        return false;
    }
    const std::string dir = new_run_folder(s, "job");
    if (dir.empty()) return false; // the error is in the log
    try {
        const auto names = method_names();
        // The search the panel would start: its method and start.
        std::vector<std::string> options = {"--method",
                                            names[std::size_t(s.method) % names.size()]};
        if (s.tailored_start) options.insert(options.end(), {"--start", "tailored"});
        const WrittenJob w = write_cluster_job({.dir = dir,
                                                .scene = edited_scene(s),
                                                .optimize_options = options,
                                                .fird = this_program(),
                                                .shape = s.cluster.shape});
        s.cluster.written = w;
        add_log(s,
                fmt::format("job written in {}: {} here, {} under Slurm", dir, w.mpirun, w.sbatch));
        follow_folder(s, dir);
        return true;
    } catch (const std::exception& e) {
        add_log(s, fmt::format("error: {}", e.what()));
        return false;
    }
}

void cluster_section(Frame& f) {
    WorkbenchState& s = f.state;
    if (std::exchange(s.cluster.reveal, false)) ImGui::SetNextItemOpen(true);
    if (!ImGui::CollapsingHeader("Cluster: write a job, follow a folder")) return;
    ClusterShape& shape = s.cluster.shape;
    count_field("ranks", shape.ranks, "run.sh: mpirun's ranks on one machine (one per device)");
    ImGui::SameLine();
    count_field("nodes", shape.nodes, "slurm.sh: nodes");
    ImGui::SameLine();
    count_field("GPUs/node", shape.gpus_per_node, "slurm.sh: GPUs per node, one rank each");
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 7);
    ImGui::InputText("time limit", &shape.time_limit);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 7);
    ImGui::InputTextWithHint("partition", "default", &shape.partition);
    const auto why = cluster_shape_error(shape);
    if (why) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", why->c_str());
    const bool can = s.editor.scene && (!s.editor.scene->reflector.optimize.empty() ||
                                        !s.editor.scene->source_optimize.empty());
    ImGui::BeginDisabled(!can || why.has_value());
    if (ImGui::Button("write job")) (void)write_job(f);
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("the scene as shown and the method above, in a new folder under the "
                          "runs folder: scene.toml, run.sh (mpirun) and slurm.sh (sbatch); then "
                          "follows that folder");
    if (s.cluster.written) {
        command_line("mpirun", s.cluster.written->mpirun);
        command_line("sbatch", s.cluster.written->sbatch);
    }
    ImGui::TextUnformatted("follow");
    ImGui::SameLine();
    const bool following = !s.follow.dir.empty();
    ImGui::SetNextItemWidth(-ImGui::GetFontSize() * 9);
    const bool entered =
        ImGui::InputTextWithHint("##follow", "a search's --out folder", &s.follow.typed,
                                 ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if (following) {
        if (ImGui::Button("stop following")) stop_following(s);
    } else if ((ImGui::Button("follow") || entered) && !s.follow.typed.empty()) {
        follow_folder(s, s.follow.typed);
    }
    if (!s.follow.error.empty() && !following)
        ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", s.follow.error.c_str());
}

} // namespace fird::ui
