// The scene panel's finish editor: the reflector's reflectance and spread lobe, and whether
// the far field bins the direct light; and the script's `material KEY VALUE`. Every edit
// goes through set_finish, which checks it as a scene file would be checked.
#include <fmt/format.h>
#include <imgui.h>

#include "panels.hpp"

namespace fird::ui {

void material_section(WorkbenchState& s) {
    if (!s.editor.scene || !ImGui::CollapsingHeader("Material and direct light")) return;
    MaterialDesc edit = s.editor.scene->reflector.material;
    DirectLight direct = s.editor.scene->trace.direct;
    bool changed = false;
    float reflectance = float(edit.reflectance);
    // Applied on release: a drag would trace at every step.
    ImGui::SliderFloat("reflectance", &reflectance, 0.0f, 1.0f, "%.3f");
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        edit.reflectance = reflectance;
        changed = true;
    }
    float spread = float(edit.spread_deg);
    ImGui::SliderFloat("spread deg", &spread, 0.0f, float(kMaxSpread_deg), "%.2f");
    if (ImGui::IsItemDeactivatedAfterEdit()) {
        edit.spread_deg = spread;
        changed = true;
    }
    int lobe = edit.lobe == SpreadLobe::Phong ? 1 : 0;
    const char* lobes[] = {"gaussian", "phong"};
    if (ImGui::Combo("lobe", &lobe, lobes, 2)) {
        edit.lobe = lobe == 1 ? SpreadLobe::Phong : SpreadLobe::Gaussian;
        changed = true;
    }
    bool include = direct == DirectLight::Include;
    if (ImGui::Checkbox("bin the direct light", &include)) {
        direct = include ? DirectLight::Include : DirectLight::Exclude;
        changed = true;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("as a measured luminaire file holds it (the paper leaves it out)");
    if (changed) (void)set_finish(s, edit, direct);
}

std::string set_material_field(WorkbenchState& s, const std::string& key,
                               const std::string& value) {
    if (!s.editor.scene) return "no scene is open";
    MaterialDesc edit = s.editor.scene->reflector.material;
    DirectLight direct = s.editor.scene->trace.direct;
    try {
        if (key == "reflectance") {
            edit.reflectance = std::stod(value);
        } else if (key == "spread_deg") {
            edit.spread_deg = std::stod(value);
        } else if (key == "lobe") {
            if (value != "gaussian" && value != "phong") return "lobe must be gaussian or phong";
            edit.lobe = value == "phong" ? SpreadLobe::Phong : SpreadLobe::Gaussian;
        } else if (key == "direct") {
            if (value != "include" && value != "exclude")
                return "direct must be include or exclude";
            direct = value == "include" ? DirectLight::Include : DirectLight::Exclude;
        } else {
            return fmt::format("no material key '{}' (reflectance, spread_deg, lobe, direct)", key);
        }
    } catch (const std::exception&) {
        return fmt::format("{}: cannot read '{}' as its value", key, value);
    }
    return set_finish(s, edit, direct) ? "" : s.editor.error;
}

} // namespace fird::ui
