// The scene panel's source editor: the emitter's type, place, tilt, size and flux, and the
// script's `source KEY VALUE`. Every edit goes through set_source, which checks it as a
// scene file would be checked.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include "model/ray_file_source.hpp"
#include "panels.hpp"
#include "photometry/candela_table.hpp"
#include "photometry/photometry_file.hpp"

namespace fird::ui {

namespace {

// The source types in SourceKind's order, named as in a scene file.
std::array<const char*, 7> type_names() {
    std::array<const char*, 7> names{};
    for (std::size_t k = 0; k < names.size(); ++k)
        names[k] = source_type_name(SourceKind(k));
    return names;
}

bool input_vec3(const char* label, glm::dvec3& v) {
    float f[3] = {float(v.x), float(v.y), float(v.z)};
    if (!ImGui::InputFloat3(label, f, "%.3f", ImGuiInputTextFlags_EnterReturnsTrue)) return false;
    v = {f[0], f[1], f[2]};
    return true;
}

bool input_mm(const char* label, double& v) {
    float f = float(v);
    if (!ImGui::InputFloat(label, &f, 0.1f, 1.0f, "%.3f", ImGuiInputTextFlags_EnterReturnsTrue))
        return false;
    v = f;
    return true;
}

// A new type keeps the place and gets a size of a few millimetres where it had none; a
// photometric one emits the editor's file (absolute: it is found from any scene) with
// that file's flux.
void change_type(SourceDesc& s, SourceKind kind, const std::string& file) {
    s.kind = kind;
    if (kind == SourceKind::RayFile) {
        s.file = file.empty() ? "" : std::filesystem::absolute(file).lexically_normal().string();
        // The file's own flux where it gives one; an unreadable file is left for
        // set_source to refuse, naming it.
        try {
            const double flux_lm = index_ray_file(s.file)->file_flux_lm;
            if (std::isfinite(flux_lm)) s.flux_lm = flux_lm;
        } catch (const std::exception&) {
        }
        return;
    }
    if (kind == SourceKind::Photometric) {
        s.file = file.empty() ? "" : std::filesystem::absolute(file).lexically_normal().string();
        s.radius_mm = 0.0;
        // The file's own flux (as a scene without flux_lm has); an unreadable file is left
        // for set_source to refuse, naming it.
        try {
            s.flux_lm = integrated_flux_lm(read_photometry(s.file));
        } catch (const std::exception&) {
        }
        return;
    }
    if (s.radius_mm <= 0.0) s.radius_mm = 1.0;
    if (kind == SourceKind::Cylinder && s.length_mm <= 0.0) s.length_mm = 10.0;
    if (kind == SourceKind::Rectangle && (s.width_mm <= 0.0 || s.height_mm <= 0.0))
        s.width_mm = s.height_mm = 2.0;
}

std::vector<double> numbers(const std::string& text) {
    std::vector<double> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
        out.push_back(std::stod(item));
    return out;
}

} // namespace

void source_section(WorkbenchState& s) {
    if (!s.editor.scene || !ImGui::CollapsingHeader("Source")) return;
    SourceDesc edit = s.editor.scene->source;
    bool changed = false;
    int type = int(edit.kind);
    const auto names = type_names();
    if (ImGui::Combo("type", &type, names.data(), int(names.size()))) {
        change_type(edit, SourceKind(type), s.editor.emitter_file);
        changed = true;
    }
    // Enter on a file makes the source that file's distribution, or its rays.
    if (ImGui::InputTextWithHint("emitter file", "an IES / LDT or ray file to emit (Enter)",
                                 &s.editor.emitter_file, ImGuiInputTextFlags_EnterReturnsTrue)) {
        change_type(edit, file_source_kind(s.editor.emitter_file), s.editor.emitter_file);
        changed = true;
    }
    changed |= input_vec3("center mm", edit.center_mm);
    switch (edit.kind) {
    case SourceKind::Cylinder:
        changed |= input_vec3("axis", edit.axis);
        changed |= input_mm("length mm", edit.length_mm);
        changed |= input_mm("radius mm", edit.radius_mm);
        break;
    case SourceKind::Sphere:
        changed |= input_mm("radius mm", edit.radius_mm);
        break;
    case SourceKind::Point: {
        bool cosine = edit.emittance == Emittance::Cosine;
        if (ImGui::Checkbox("cosine (else isotropic)", &cosine)) {
            edit.emittance = cosine ? Emittance::Cosine : Emittance::Isotropic;
            changed = true;
        }
        if (cosine) changed |= input_vec3("axis", edit.axis);
        break;
    }
    case SourceKind::Photometric:
        ImGui::TextWrapped("%s", edit.file.c_str());
        changed |= input_vec3("normal", edit.axis);
        changed |= input_vec3("x axis", edit.x_axis);
        changed |= input_mm("disk radius mm", edit.radius_mm);
        break;
    case SourceKind::RayFile:
        ImGui::TextWrapped("%s", edit.file.c_str());
        changed |= input_vec3("normal", edit.axis);
        changed |= input_vec3("x axis", edit.x_axis);
        break;
    case SourceKind::Disk:
    case SourceKind::Rectangle:
        changed |= input_vec3("normal", edit.axis);
        changed |= input_vec3("x axis", edit.x_axis);
        if (edit.kind == SourceKind::Disk) {
            changed |= input_mm("radius mm", edit.radius_mm);
        } else {
            changed |= input_mm("width mm", edit.width_mm);
            changed |= input_mm("height mm", edit.height_mm);
        }
        break;
    }
    changed |= input_mm("flux lm", edit.flux_lm);
    if (changed) (void)set_source(s, edit);
}

std::string set_source_field(WorkbenchState& s, const std::string& key, const std::string& value) {
    if (!s.editor.scene) return "no scene is open";
    SourceDesc edit = s.editor.scene->source;
    try {
        const auto vec = [&](glm::dvec3& v) {
            const std::vector<double> n = numbers(value);
            if (n.size() != 3) throw std::invalid_argument("three numbers, as 0,0,-1");
            v = {n[0], n[1], n[2]};
        };
        if (key == "type") {
            const auto names = type_names();
            const auto it =
                std::find_if(names.begin(), names.end(), [&](const char* n) { return value == n; });
            if (it == names.end())
                return "type must be one of: cylinder, sphere, point, disk, rectangle, "
                       "photometric, rayfile";
            if ((value == "photometric" || value == "rayfile") && s.editor.emitter_file.empty())
                return fmt::format("type {}: give its file first (source file PATH)", value);
            change_type(edit, SourceKind(it - names.begin()), s.editor.emitter_file);
        } else if (key == "file") {
            s.editor.emitter_file = value;
            change_type(edit, file_source_kind(value), value);
        } else if (key == "center_mm") {
            vec(edit.center_mm);
        } else if (key == "normal" || key == "axis") {
            vec(edit.axis);
        } else if (key == "x_axis") {
            vec(edit.x_axis);
        } else if (key == "radius_mm") {
            edit.radius_mm = std::stod(value);
        } else if (key == "length_mm") {
            edit.length_mm = std::stod(value);
        } else if (key == "size_mm") {
            const std::vector<double> n = numbers(value);
            if (n.size() != 2) return "size_mm: two numbers, as 4,1";
            edit.width_mm = n[0];
            edit.height_mm = n[1];
        } else if (key == "flux_lm") {
            edit.flux_lm = std::stod(value);
        } else if (key == "emittance") {
            if (value != "cosine" && value != "isotropic")
                return "emittance must be cosine or isotropic";
            edit.emittance = value == "cosine" ? Emittance::Cosine : Emittance::Isotropic;
        } else {
            return fmt::format("no source key '{}' (type, file, center_mm, normal, axis, x_axis, "
                               "radius_mm, length_mm, size_mm, flux_lm, emittance)",
                               key);
        }
    } catch (const std::exception&) {
        return fmt::format("{}: cannot read '{}' as its value", key, value);
    }
    return set_source(s, edit) ? "" : s.editor.error;
}

} // namespace fird::ui
