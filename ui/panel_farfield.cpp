// The far-field panel: desired, obtained and difference (or one of them, filling the
// panel) in the columns that keep each readable, zoom onto the lit band's brightest part,
// linear or log, a hover readout of the cell under the mouse (in the luminaire views, of
// the direction or the plane's point), l2 and flux.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <imgui.h>
#include <imgui_internal.h> // SetItemUsingMouseWheel: the wheel zooms, not scrolls

#include "photometry/luminaire_pictures.hpp"

#include "panels.hpp"
#include "view_textures.hpp"
#include "views.hpp"

namespace fird::ui {

namespace {

// The readout's lines: which panel, where, and the obtained, desired and difference values
// (the isocandela view's third panel overlays the two tables' lines).
std::string luminaire_readout_text(const LuminaireReadout& r, bool isocandela) {
    const char* panel = r.panel == LuminairePanel::Obtained  ? "obtained"
                        : r.panel == LuminairePanel::Desired ? "desired"
                        : isocandela ? "obtained (solid) and desired (dashed)"
                                     : "obtained - desired";
    const char* unit = r.on_plane ? "lx" : "cd";
    std::string text = fmt::format("{}\n", panel);
    if (r.on_plane)
        text += fmt::format("x {:.3g} m (along C0), y {:.3g} m (along C90)\n", r.x_m, r.y_m);
    text += fmt::format("C {:.1f} deg, gamma {:.1f} deg from nadir\nobtained {:.4g} {}", r.c_deg,
                        r.gamma_deg, r.obtained, unit);
    if (r.desired)
        text += fmt::format("\ndesired {:.4g} {}\ndifference {:+.4g} {}", *r.desired, unit,
                            r.obtained - *r.desired, unit);
    return text;
}

} // namespace

void farfield_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::FarField);
    ImGui::Checkbox("log scale", &s.farfield.log_scale);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(8.0f * ImGui::GetFontSize());
    ImGui::SliderFloat("zoom", &s.farfield.zoom, 1.0f, 8.0f, "%.1fx");
    ImGui::SameLine();
    const char* shown[] = {"all", "desired", "obtained", "difference"};
    ImGui::SetNextItemWidth(7.0f * ImGui::GetFontSize());
    ImGui::Combo("maps", &s.farfield.maps, shown, 4);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("one map alone fills the panel");
    ImGui::SameLine();
    const char* views[] = {"far field", "polar map", "isocandela", "illuminance"};
    ImGui::SetNextItemWidth(8.0f * ImGui::GetFontSize());
    ImGui::Combo("view", &s.farfield.view, views, 4);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the equirectangular maps, or what a lighting engineer reads: the "
                          "intensity around nadir, isocandela lines in C-gamma, the illuminance "
                          "on a plane below; each beside the desired one and the difference");
    if (s.farfield.view == 3) { // on its own line: the toolbar is full
        ImGui::SetNextItemWidth(8.0f * ImGui::GetFontSize());
        ImGui::SliderFloat("plane", &s.farfield.plane_distance_m, 0.5f, 20.0f, "%.1f m",
                           ImGuiSliderFlags_Logarithmic | ImGuiSliderFlags_AlwaysClamp);
    }
    if (!f.snapshot) {
        ImGui::TextDisabled("no trace yet");
        ImGui::End();
        return;
    }
    const auto& ff = f.snapshot->traced.farfield;
    ImGui::Text("obtained %.3f lm", f.snapshot->obtained_lm);
    if (ff.desired) {
        ImGui::SameLine();
        const FarFieldMetric metric = f.snapshot->traced.scene.optimize.metric;
        ImGui::Text("| desired %.3f lm | %s %.5g %s", f.snapshot->desired_lm, metric_name(metric),
                    ff.l2_lm.value_or(0.0), metric_unit(metric));
    }
    // The maps in the columns that keep each readable; below their least height they keep
    // it and the panel scrolls.
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const std::size_t n = s.farfield.maps != 0 || !ff.desired || s.farfield.view > 0 ? 1 : 3;
    render::FarFieldViewGrid grid = render::farfield_view_grid(avail.x, avail.y, n);
    const bool scrolls = grid.height > avail.y + 0.5f;
    float w = avail.x;
    if (scrolls) {
        ImGui::BeginChild("##maps_scroll", avail, false, ImGuiWindowFlags_AlwaysVerticalScrollbar);
        w -= ImGui::GetStyle().ScrollbarSize;
        grid = render::farfield_view_grid(w, avail.y, n);
    }
    const render::FarFieldViewOptions options = farfield_view_options(s, *f.snapshot, grid.columns);
    const auto iw = std::uint32_t(std::max(200.0f, w)),
               ih = std::uint32_t(std::max(120.0, grid.height));
    update_farfield_image(f.ctx, s, f.snapshot, options, iw, ih);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    // The maps own their mouse (an invisible button over the image): the wheel zooms the
    // band, a double click shows it whole, and nothing drags the window.
    ImGui::InvisibleButton("##maps", ImVec2(float(iw), float(ih)));
    ImGui::SetItemUsingMouseWheel();
    if (s.farfield_image.texture) // none until the first redraw has finished
        ImGui::GetWindowDrawList()->AddImage(
            static_cast<ImTextureID>(s.farfield_image.texture.get()), origin,
            ImVec2(origin.x + float(iw), origin.y + float(ih)));
    if (ImGui::IsItemHovered() && s.farfield.view == 0) { // the maps' zoom and readout
        const float wheel = ImGui::GetIO().MouseWheel;
        if (wheel != 0.0f)
            s.farfield.zoom = std::clamp(s.farfield.zoom * std::pow(1.25f, wheel), 1.0f, 8.0f);
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) s.farfield.zoom = 1.0f;
        // The cell under the mouse, in whichever map it is over (the placement is the
        // drawing's own, with the same options, so the readout follows the maps at any
        // panel size, selection and zoom).
        const ImVec2 m = ImGui::GetIO().MousePos;
        const auto maps = render::farfield_view_maps({0, 0, double(iw), double(ih)}, ff, options);
        if (const auto at =
                render::farfield_cell_at(maps, ff.obtained, m.x - origin.x, m.y - origin.y)) {
            const FarField& grid_ff = ff.obtained;
            const std::size_t cell = std::size_t(at->row) * grid_ff.width + at->column;
            const double obtained = grid_ff.lm[cell];
            const double desired = ff.desired ? ff.desired->lm[cell] : 0.0;
            using K = render::FarFieldMapKind;
            const double lm = at->kind == K::Desired    ? desired
                              : at->kind == K::Obtained ? obtained
                                                        : obtained - desired;
            const char* name = at->kind == K::Desired    ? "desired"
                               : at->kind == K::Obtained ? "obtained"
                                                         : "obtained - desired";
            ImGui::SetTooltip(
                "%s\nazimuth phi %.1f deg, altitude theta %.1f deg\n%.4g lm, %.4g cd", name,
                -180.0 + (at->column + 0.5) * 360.0 / grid_ff.width,
                90.0 - (at->row + 0.5) * 180.0 / grid_ff.height, lm,
                lm / farfield_cell_solid_angle_sr(at->row, grid_ff.width, grid_ff.height));
        }
    }
    if (ImGui::IsItemHovered() && s.farfield.view > 0 && f.snapshot->obtained_table) {
        // The luminaire views' readout: the direction (and point of the plane) under the
        // mouse and what each table gives there, placed as the drawing places its panels.
        const ImVec2 m = ImGui::GetIO().MousePos;
        const auto& snap = *f.snapshot;
        if (const auto at = luminaire_view_readout(
                {0, 0, double(iw), double(ih)}, *options.luminaire, *snap.obtained_table,
                snap.desired_table ? &*snap.desired_table : nullptr,
                {.title = ff.title, .plane_distance_m = options.plane_distance_m},
                snap.view_gamma_deg, m.x - origin.x, m.y - origin.y))
            ImGui::SetTooltip(
                "%s", luminaire_readout_text(*at, *options.luminaire == LuminaireView::Isocandela)
                          .c_str());
    }
    if (scrolls) ImGui::EndChild();
    ImGui::End();
}

} // namespace fird::ui
