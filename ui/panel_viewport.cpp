// The 3D viewport panel: orbit (left drag), pan (right drag), zoom (wheel), frame all
// (double click); ray paths and quadtree overlays; a ray picked by clicking, its RQRM walk
// stepped forward and back. The view owns its mouse input: an invisible button over the
// image (as Dear ImGui's canvas example) captures drags, wheel and clicks.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <imgui.h>
#include <imgui_internal.h> // SetItemUsingMouseWheel: the wheel zooms, not scrolls

#include "panels.hpp"
#include "view_textures.hpp"

namespace fird::ui {

// The sample path passing closest to the pixel's ray (distance between the lines of the
// ray and each segment), if any is within a few pixels' worth.
static std::optional<std::size_t> pick_path(const std::vector<RayPath>& paths,
                                            const render::PixelRay& ray, double tolerance_mm) {
    std::optional<std::size_t> best;
    double best_d = tolerance_mm;
    for (std::size_t i = 0; i < paths.size(); ++i)
        for (std::size_t k = 0; k + 1 < paths[i].vertices.size(); ++k) {
            const glm::dvec3 a = paths[i].vertices[k], b = paths[i].vertices[k + 1];
            // Closest points of the pixel ray and segment ab.
            const glm::dvec3 u = ray.direction, v = b - a, w0 = ray.origin - a;
            const double aa = glm::dot(u, u), bb = glm::dot(u, v), cc = glm::dot(v, v);
            const double dd = glm::dot(u, w0), ee = glm::dot(v, w0);
            const double den = aa * cc - bb * bb;
            double sv = den > 1e-12 ? std::clamp((aa * ee - bb * dd) / den, 0.0, 1.0) : 0.0;
            const double su = std::max(0.0, (bb * sv - dd) / aa);
            const double dist = glm::length((ray.origin + su * u) - (a + sv * v));
            if (dist < best_d) best_d = dist, best = i;
        }
    return best;
}

bool pick_at(Frame& f, float px, float py) {
    WorkbenchState& s = f.state;
    if (!f.snapshot || s.viewport_w <= 0) return false;
    ViewportState& v = s.viewport;
    const render::PixelRay ray = render::pixel_ray(v.camera, px, py, s.viewport_w, s.viewport_h);
    const double tolerance = 6.0 * v.camera.distance_mm / double(s.viewport_h);
    const auto picked = pick_path(f.snapshot->traced.viewport.paths, ray, tolerance);
    if (!picked) return false;
    v.picked_path = picked;
    v.walk_step = std::numeric_limits<std::size_t>::max() / 2;
    request_trace(f); // records the picked ray's walk
    return true;
}

// What the ray colours mean: each segment of a path is coloured by the reflections
// before it (render::bounce_colour; later reflections in further colours), a picked ray
// in black.
static void ray_legend() {
    const char* labels[] = {"from the source", "after 1 reflection", "2", "3"};
    for (std::uint32_t b = 0; b < 4; ++b) {
        const auto c = render::bounce_colour(b);
        ImGui::SameLine();
        ImGui::ColorButton(labels[b], ImVec4(c[0], c[1], c[2], 1.0f),
                           ImGuiColorEditFlags_NoTooltip | ImGuiColorEditFlags_NoDragDrop,
                           ImVec2(ImGui::GetTextLineHeight(), ImGui::GetTextLineHeight()));
        ImGui::SameLine(0.0f, 4.0f);
        ImGui::TextUnformatted(labels[b]);
    }
}

// The holder fills the view, seen from the camera's direction.
static render::OrbitCamera framed_all(const render::OrbitCamera& camera, const Holder& holder) {
    render::OrbitCamera c = render::frame_holder(holder);
    c.azimuth_deg = camera.azimuth_deg, c.elevation_deg = camera.elevation_deg;
    return c;
}

void viewport_panel(Frame& f) {
    WorkbenchState& s = f.state;
    begin_panel(f, PanelId::Viewport);
    ViewportState& v = s.viewport;
    ImGui::Checkbox("rays", &v.options.rays);
    ImGui::SameLine();
    ImGui::Checkbox("quadtree", &v.options.quadtree);
    ImGui::SameLine();
    int level = int(v.options.quadtree_level);
    ImGui::SetNextItemWidth(100);
    if (ImGui::SliderInt("level", &level, 0, 12)) v.options.quadtree_level = std::uint32_t(level);
    ImGui::SameLine();
    ImGui::Checkbox("height colours", &v.options.height_colours);
    if (!f.snapshot) {
        ImGui::TextDisabled("no trace yet");
        ImGui::End();
        return;
    }
    const auto& content = f.snapshot->traced.viewport;
    // A scene just opened is framed on its own first trace, not on the last scene's.
    const bool stale = v.stale_generation && f.snapshot->generation <= *v.stale_generation;
    v.shown_generation = f.snapshot->generation;
    if (!v.camera_set && !stale) {
        v.camera = render::frame_holder(content.holder);
        v.camera_set = true;
        v.frame_all = false;
    }
    if (v.frame_all) {
        v.camera = framed_all(v.camera, content.holder);
        v.frame_all = false;
    }
    if (v.picked_path) {
        const std::size_t steps = content.picked == v.picked_path ? content.walk.size() : 0;
        ImGui::Text("ray %zu: walk step %zu of %zu", *v.picked_path, std::min(v.walk_step, steps),
                    steps);
        ImGui::SameLine();
        if (ImGui::Button("<") && v.walk_step > 0) --v.walk_step;
        ImGui::SameLine();
        if (ImGui::Button(">") && v.walk_step < steps) ++v.walk_step;
        ImGui::SameLine();
        if (ImGui::Button("all")) v.walk_step = steps;
        ImGui::SameLine();
        if (ImGui::Button("unpick")) v.picked_path.reset();
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const auto w = std::uint32_t(std::max(64.0f, avail.x)),
               h = std::uint32_t(std::max(64.0f, avail.y - ImGui::GetTextLineHeightWithSpacing()));
    update_viewport_image(f.ctx, f.renderer, s, *f.snapshot, w, h);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    s.viewport_x = origin.x, s.viewport_y = origin.y, s.viewport_w = float(w),
    s.viewport_h = float(h);
    ImGui::InvisibleButton("##view", ImVec2(float(w), float(h)),
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    ImGui::SetItemUsingMouseWheel();
    ImGui::GetWindowDrawList()->AddImage(static_cast<ImTextureID>(s.viewport_image.texture.get()),
                                         origin, ImVec2(origin.x + float(w), origin.y + float(h)));
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
        v.camera.azimuth_deg -= 0.4 * io.MouseDelta.x;
        v.camera.elevation_deg =
            std::clamp(v.camera.elevation_deg + 0.4 * io.MouseDelta.y, -89.0, 89.0);
    }
    if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
        const double az = v.camera.azimuth_deg * M_PI / 180.0;
        const double scale = v.camera.distance_mm / double(h);
        v.camera.target +=
            scale * (double(io.MouseDelta.x) * glm::dvec3(std::sin(az), -std::cos(az), 0.0) +
                     double(io.MouseDelta.y) * glm::dvec3(0, 0, 1));
    }
    if (ImGui::IsItemHovered()) {
        if (io.MouseWheel != 0.0f) v.camera.distance_mm *= std::pow(0.9, double(io.MouseWheel));
        if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left))
            v.camera = framed_all(v.camera, content.holder);
        else if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
                 io.MouseDragMaxDistanceSqr[0] < 9.0f)
            (void)pick_at(f, io.MousePos.x - origin.x, io.MousePos.y - origin.y);
    }
    if (ImGui::SmallButton("frame all")) v.camera = framed_all(v.camera, content.holder);
    ImGui::SameLine();
    if (ImGui::SmallButton("reset view")) v.camera = render::frame_holder(content.holder);
    ImGui::SameLine();
    ImGui::TextDisabled("(?)");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("left drag orbits, right drag pans, the wheel zooms,\n"
                          "a double click frames all, a click picks a ray");
    if (v.options.rays) ray_legend();
    ImGui::End();
}

} // namespace fird::ui
