// The far-field panel: desired, obtained and difference with the polar curves, zoom to
// the lit band, linear or log, a hover readout of the cell under the mouse, l2 and flux.
#include <algorithm>
#include <cmath>

#include <imgui.h>
#include <imgui_internal.h> // SetItemUsingMouseWheel: the wheel zooms, not scrolls

#include "panels.hpp"
#include "view_textures.hpp"
#include "views.hpp"

namespace fird::ui {

void farfield_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::FarField);
    ImGui::Checkbox("log scale", &s.farfield.log_scale);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(160);
    ImGui::SliderFloat("zoom", &s.farfield.zoom, 1.0f, 8.0f, "%.1fx");
    if (!f.snapshot) {
        ImGui::TextDisabled("no trace yet");
        ImGui::End();
        return;
    }
    const auto& ff = f.snapshot->traced.farfield;
    ImGui::Text("obtained %.3f lm", ff.obtained.total_lm());
    if (ff.desired) {
        ImGui::SameLine();
        ImGui::Text("| desired %.3f lm | l2 %.5g lm", ff.desired->total_lm(),
                    ff.l2_lm.value_or(0.0));
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const auto w = std::uint32_t(std::max(200.0f, avail.x)),
               h = std::uint32_t(std::max(200.0f, avail.y - 20));
    update_farfield_image(f.ctx, s, *f.snapshot, w, h);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    // The maps own their mouse (an invisible button over the image): the wheel zooms the
    // band, a double click shows it whole, and nothing drags the window.
    ImGui::InvisibleButton("##maps", ImVec2(float(w), float(h)));
    ImGui::SetItemUsingMouseWheel();
    ImGui::GetWindowDrawList()->AddImage(static_cast<ImTextureID>(s.farfield_image.texture.get()),
                                         origin, ImVec2(origin.x + float(w), origin.y + float(h)));
    if (ImGui::IsItemHovered()) {
        const float wheel = ImGui::GetIO().MouseWheel;
        if (wheel != 0.0f)
            s.farfield.zoom = std::clamp(s.farfield.zoom * std::pow(1.25f, wheel), 1.0f, 8.0f);
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) s.farfield.zoom = 1.0f;
        // The cell under the mouse, in whichever map it is over (the placement is the
        // drawing's own, so the readout follows the maps at any panel size and zoom).
        const ImVec2 m = ImGui::GetIO().MousePos;
        const double px = m.x - origin.x, py = m.y - origin.y;
        const auto maps = render::farfield_view_maps(
            {0, 0, double(w), double(h)}, ff,
            {.log_scale = s.farfield.log_scale, .altitude_deg = farfield_band(s, ff.obtained)});
        if (const auto at = render::farfield_cell_at(maps, ff.obtained, px, py)) {
            const FarField& grid = ff.obtained;
            const std::size_t cell = std::size_t(at->row) * grid.width + at->column;
            const double obtained = grid.lm[cell];
            const double desired = ff.desired ? ff.desired->lm[cell] : 0.0;
            using K = render::FarFieldMapKind;
            const double lm = at->kind == K::Desired    ? desired
                              : at->kind == K::Obtained ? obtained
                                                        : obtained - desired;
            const char* name = at->kind == K::Desired    ? "desired"
                               : at->kind == K::Obtained ? "obtained"
                                                         : "obtained - desired";
            ImGui::SetTooltip("%s\nazimuth phi %.1f deg, altitude theta %.1f deg\n%.4g lm, %.4g cd",
                              name, -180.0 + (at->column + 0.5) * 360.0 / grid.width,
                              90.0 - (at->row + 0.5) * 180.0 / grid.height, lm,
                              lm / farfield_cell_solid_angle_sr(at->row, grid.width, grid.height));
        }
    }
    ImGui::End();
}

} // namespace fird::ui
