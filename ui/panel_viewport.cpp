// The 3D viewport panel: orbit (left drag), pan (right drag), zoom (wheel), frame all
// (double click); ray paths and quadtree overlays; a ray picked by clicking, its RQRM walk
// stepped forward and back, each step described. The view owns its mouse input: an invisible button
// over the image (as Dear ImGui's canvas example) captures drags, wheel and clicks.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
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
    const auto& paths = f.snapshot->traced.viewport.paths;
    const auto picked = pick_path(paths, ray, tolerance);
    if (!picked) return false;
    pick_index(f, paths[*picked].ray_index); // the ray's identity, not its place in the list
    return true;
}

void pick_index(Frame& f, std::uint64_t index) {
    if (!f.snapshot) throw std::logic_error("nothing is traced yet");
    const render::TracedScene& traced = f.snapshot->traced;
    (void)effective_ray(render::rayset_scene(traced), index); // a one-line error, at once
    ViewportState& v = f.state.viewport;
    v.picked_ray = index;
    v.picked_rayset_rays = traced.rayset_rays;
    v.walk_step = std::numeric_limits<std::size_t>::max(); // its last step, once it is there
    v.pick_asked_generation = f.snapshot->generation;
    f.worker.submit(PickJob{f.snapshot, index}); // this ray alone, not the scene
}

const PickedRay* shown_pick(const Frame& f) {
    const ViewportState& v = f.state.viewport;
    if (!v.picked_ray || !f.snapshot) return nullptr;
    const auto& traced = f.snapshot->traced.viewport.picked;
    if (traced && traced->index == *v.picked_ray) return &*traced;
    if (f.picked && f.picked->generation == f.snapshot->generation &&
        f.picked->ray.index == *v.picked_ray)
        return &f.picked->ray;
    return nullptr;
}

// Keeps the pick on the trace shown: a new trace (a moved slider, the full trace after the
// preview) re-traces the picked ray alone through its reflector; a trace of another
// rayset (another ray count) has another ray under that index, so the pick is dropped.
static void follow_pick(Frame& f) {
    ViewportState& v = f.state.viewport;
    if (!v.picked_ray || !f.snapshot) return;
    if (f.snapshot->traced.rayset_rays != v.picked_rayset_rays) {
        add_log(f.state,
                fmt::format("unpicked ray {}: the trace shown has a rayset of {} rays, "
                            "it was picked in one of {}",
                            *v.picked_ray, f.snapshot->traced.rayset_rays, v.picked_rayset_rays));
        v.picked_ray.reset();
        return;
    }
    if (!shown_pick(f) && v.pick_asked_generation != f.snapshot->generation) {
        v.pick_asked_generation = f.snapshot->generation;
        f.worker.submit(PickJob{f.snapshot, *v.picked_ray});
    }
}

// The picked ray's walk: the step buttons, and every step described in a scrolling list
// (the current one highlighted, scrolled into view when a button moves it).
static void walk_steps(ViewportState& v, const PickedRay& p) {
    const std::size_t n = p.walk.size();
    if (n == 0) {
        ImGui::TextDisabled("no walk steps (the ray leaves the holder before any node)");
        return;
    }
    v.walk_step = std::min(v.walk_step, n - 1);
    if (ImGui::SmallButton("first")) v.walk_step = 0;
    ImGui::SameLine();
    if (ImGui::SmallButton("<") && v.walk_step > 0) --v.walk_step;
    ImGui::SameLine();
    if (ImGui::SmallButton(">") && v.walk_step + 1 < n) ++v.walk_step;
    ImGui::SameLine();
    if (ImGui::SmallButton("last")) v.walk_step = n - 1;
    ImGui::SameLine();
    ImGui::Checkbox("trail", &v.walk_trail);
    ImGui::SameLine();
    ImGui::Text("step %zu of %zu", v.walk_step + 1, n);
    const float row = ImGui::GetTextLineHeightWithSpacing();
    ImGui::BeginChild("##walk", ImVec2(0.0f, 6.0f * row), true,
                      ImGuiWindowFlags_HorizontalScrollbar);
    if (v.walk_scrolled_to != v.walk_step) {
        ImGui::SetScrollY(std::max(0.0f, float(v.walk_step) * row - 2.5f * row));
        v.walk_scrolled_to = v.walk_step;
    }
    ImGuiListClipper clipper;
    clipper.Begin(int(n), row);
    while (clipper.Step())
        for (int k = clipper.DisplayStart; k < clipper.DisplayEnd; ++k) {
            const std::string text = fmt::format("{:4d}  {}", k + 1, describe_walk_step(p.walk[k]));
            if (ImGui::Selectable(text.c_str(), std::size_t(k) == v.walk_step))
                v.walk_step = v.walk_scrolled_to = std::size_t(k);
        }
    ImGui::EndChild();
    ImGui::TextWrapped("%s", walk_step_reason(p.walk[v.walk_step]).c_str());
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

// The slope or curvature colours' scale, and the marked point's value (a line of its own,
// below the buttons).
static void press_legend(const render::ViewportOptions& o, const render::ViewportContent& c) {
    if (!o.slope_colours && !o.curvature_colours) return;
    const bool bends = o.curvature_colours;
    if (bends)
        ImGui::Text("bend radius: blue %g mm or flatter, yellow %g mm or tighter",
                    render::kCurvatureFlatRadiusMm, render::kCurvatureTightRadiusMm);
    else
        ImGui::TextUnformatted("slope: blue 0, yellow 90 deg");
    if (bends && c.tightest_mm) {
        ImGui::SameLine();
        if (c.min_radius_mm > 0.0)
            ImGui::Text("; x tightest %.3g mm", c.min_radius_mm);
        else
            ImGui::TextUnformatted("; x a kink");
    } else if (!bends && c.steepest_mm) {
        ImGui::SameLine();
        ImGui::TextUnformatted("; x steepest");
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
    ImGui::SameLine();
    // Slope and curvature colour the same surface: one at a time.
    if (ImGui::Checkbox("slope", &v.options.slope_colours) && v.options.slope_colours)
        v.options.curvature_colours = false;
    ImGui::SameLine();
    if (ImGui::Checkbox("curvature", &v.options.curvature_colours) && v.options.curvature_colours)
        v.options.slope_colours = false;
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
    follow_pick(f);
    const PickedRay* picked = shown_pick(f);
    if (v.picked_ray) {
        ImGui::Text("ray %llu of the %llu-ray rayset",
                    static_cast<unsigned long long>(*v.picked_ray),
                    static_cast<unsigned long long>(v.picked_rayset_rays));
        ImGui::SameLine();
        if (ImGui::SmallButton("unpick")) v.picked_ray.reset(), picked = nullptr;
        if (picked)
            walk_steps(v, *picked);
        else if (v.picked_ray)
            ImGui::TextDisabled("tracing the ray...");
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    // Below the image: the buttons' line, and the press colours' scale where shown.
    const float below = ImGui::GetTextLineHeightWithSpacing() *
                        (v.options.slope_colours || v.options.curvature_colours ? 2.0f : 1.0f);
    const auto w = std::uint32_t(std::max(64.0f, avail.x)),
               h = std::uint32_t(std::max(64.0f, avail.y - below));
    update_viewport_image(f.ctx, f.renderer, s, f.snapshot, picked, w, h);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    s.viewport_x = origin.x, s.viewport_y = origin.y, s.viewport_w = float(w),
    s.viewport_h = float(h);
    ImGui::InvisibleButton("##view", ImVec2(float(w), float(h)),
                           ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
    ImGui::SetItemUsingMouseWheel();
    if (s.viewport_image.texture) // none until the first redraw has finished
        ImGui::GetWindowDrawList()->AddImage(
            static_cast<ImTextureID>(s.viewport_image.texture.get()), origin,
            ImVec2(origin.x + float(w), origin.y + float(h)));
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
    press_legend(v.options, content);
    ImGui::End();
}

} // namespace fird::ui
