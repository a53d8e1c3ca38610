// The 3D viewport panel: orbit (left drag), pan (right drag), zoom (wheel); ray paths and
// quadtree overlays; a ray picked by clicking, its RQRM walk stepped forward and back.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>
#include <imgui.h>

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

void viewport_panel(Frame& f) {
    WorkbenchState& s = f.state;
    ImGui::Begin("Viewport");
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
    if (!v.camera_set) {
        v.camera = render::frame_holder(content.holder);
        v.camera_set = true;
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
               h = std::uint32_t(std::max(64.0f, avail.y));
    update_viewport_image(f.ctx, f.renderer, s, *f.snapshot, w, h);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    s.viewport_x = origin.x, s.viewport_y = origin.y, s.viewport_w = float(w),
    s.viewport_h = float(h);
    ImGui::Image(static_cast<ImTextureID>(s.viewport_image.texture.get()),
                 ImVec2(float(w), float(h)));
    if (ImGui::IsItemHovered()) {
        const ImGuiIO& io = ImGui::GetIO();
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
            v.camera.azimuth_deg -= 0.4 * io.MouseDelta.x;
            v.camera.elevation_deg =
                std::clamp(v.camera.elevation_deg + 0.4 * io.MouseDelta.y, -89.0, 89.0);
        }
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
            const double az = v.camera.azimuth_deg * M_PI / 180.0;
            const double scale = v.camera.distance_mm / double(h);
            v.camera.target +=
                scale * (double(io.MouseDelta.x) * glm::dvec3(std::sin(az), -std::cos(az), 0.0) +
                         double(io.MouseDelta.y) * glm::dvec3(0, 0, 1));
        }
        if (io.MouseWheel != 0.0f) v.camera.distance_mm *= std::pow(0.9, double(io.MouseWheel));
        if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) &&
            std::abs(io.MouseDragMaxDistanceSqr[0]) < 9.0f)
            (void)pick_at(f, io.MousePos.x - origin.x, io.MousePos.y - origin.y);
    }
    ImGui::End();
}

} // namespace fird::ui
