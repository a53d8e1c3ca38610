// The far-field panel: desired, obtained and difference with the polar curves, zoom to
// the lit band, linear or log, a hover readout of the cell under the mouse, l2 and flux.
#include <algorithm>
#include <cmath>

#include <imgui.h>
#include <imgui_internal.h> // SetItemUsingMouseWheel: the wheel zooms, not scrolls

#include "panels.hpp"
#include "view_textures.hpp"

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
        // The obtained map's box (draw_farfield's layout: the middle of the stack of
        // maps, 62 % of the width, margins of 70 left and 40 / 56 top and bottom).
        const double maps = ff.desired ? 3.0 : 1.0;
        const double map_h = h / maps, x0 = 70.0, x1 = 0.62 * w - 140.0;
        const double y0 = (ff.desired ? map_h : 0.0) + 40.0,
                     y1 = (ff.desired ? 2 * map_h : map_h) - 56.0;
        const ImVec2 m = ImGui::GetIO().MousePos;
        const double px = m.x - origin.x, py = m.y - origin.y;
        if (px >= x0 && px < x1 && py >= y0 && py < y1) {
            const auto band = farfield_band(s, ff.obtained);
            const double az = -180.0 + (px - x0) / (x1 - x0) * 360.0;
            const double alt = band.first - (py - y0) / (y1 - y0) * (band.first - band.second);
            const auto col = std::uint32_t(
                std::clamp((az + 180.0) / 360.0 * ff.obtained.width, 0.0, ff.obtained.width - 1.0));
            const auto row = std::uint32_t(std::clamp((90.0 - alt) / 180.0 * ff.obtained.height,
                                                      0.0, ff.obtained.height - 1.0));
            const double lm = ff.obtained.lm[std::size_t(row) * ff.obtained.width + col];
            ImGui::SetTooltip(
                "azimuth %.1f deg, altitude %.1f deg\n%.4g lm, %.4g cd", az, alt, lm,
                lm / farfield_cell_solid_angle_sr(row, ff.obtained.width, ff.obtained.height));
        }
    }
    ImGui::End();
}

} // namespace fird::ui
