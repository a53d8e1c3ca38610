#include "view_textures.hpp"

#include <algorithm>
#include <cstring>
#include <functional>

#include "plot/farfield_picture.hpp"

namespace fird::ui {

namespace {

// FNV-1a over the values' bits: what a view was drawn from.
template <std::size_t N> std::uint64_t value_hash(const double (&values)[N]) {
    std::uint64_t hash = 1469598103934665603ull;
    for (double v : values) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, 8);
        hash = (hash ^ bits) * 1099511628211ull;
    }
    return hash;
}

std::uint64_t camera_hash(const WorkbenchState& s, const PickedRay* picked, std::uint32_t w,
                          std::uint32_t h) {
    const auto& c = s.viewport.camera;
    const auto& o = s.viewport.options;
    const double values[] = {c.target.x,
                             c.target.y,
                             c.target.z,
                             c.azimuth_deg,
                             c.elevation_deg,
                             c.distance_mm,
                             double(o.rays),
                             double(o.quadtree),
                             double(o.quadtree_level),
                             double(o.height_colours),
                             double(s.viewport.walk_step),
                             double(s.viewport.walk_trail),
                             double(w),
                             double(h),
                             picked ? double(picked->index) : -1.0,
                             picked ? double(picked->walk.size()) : -1.0};
    return value_hash(values);
}

std::vector<std::uint8_t> canvas_rgba(plot::Canvas& cv) {
    return cv.rgba();
}

} // namespace

void upload(const vk::Context& ctx, ViewTexture& t, const std::vector<std::uint8_t>& rgba,
            std::uint32_t w, std::uint32_t h, std::uint64_t generation) {
    if (!t.texture || t.width != w || t.height != h) {
        t.texture = std::make_unique<vk::Texture>(ctx, w, h, "fird.workbench.view");
        t.width = w;
        t.height = h;
    }
    t.texture->upload(ctx, rgba.data());
    t.generation = generation;
}

void update_viewport_image(const vk::Context& ctx, render::ViewportRenderer& renderer,
                           WorkbenchState& s, const SceneSnapshot& snap, const PickedRay* picked,
                           std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 64u), h = std::max(h, 64u);
    const std::uint64_t view = camera_hash(s, picked, w, h);
    if (s.viewport_image.generation == snap.generation && s.drawn_camera_hash == view) return;
    render::ViewportContent content = snap.traced.viewport;
    content.picked = picked ? std::make_optional(*picked) : std::nullopt;
    render::ViewportOptions o = s.viewport.options;
    o.camera = s.viewport.camera;
    o.walk_steps = s.viewport.walk_step + 1; // up to the current step
    o.walk_trail = s.viewport.walk_trail;
    upload(ctx, s.viewport_image, render::render_viewport(ctx, renderer, content, o, w, h), w, h,
           snap.generation);
    s.drawn_camera_hash = view;
}

std::pair<double, double> farfield_band(const WorkbenchState& s, const FarField& f) {
    const auto band = plot::lit_altitude_band(f);
    return plot::brightest_altitude_window(
        f, band, (band.first - band.second) / std::max(1.0f, s.farfield.zoom));
}

render::FarFieldViewOptions farfield_view_options(const WorkbenchState& s,
                                                  const render::FarFieldContent& c, int columns) {
    using K = render::FarFieldMapKind;
    std::optional<K> only;
    if (s.farfield.maps == 1) only = K::Desired;
    if (s.farfield.maps == 2) only = K::Obtained;
    if (s.farfield.maps == 3) only = K::Difference;
    // The zoom narrows both axes about the brightest part of the lit band (an azimuth band
    // that spans the whole circle is narrowed too: its brightest arc is shown).
    const auto across = plot::lit_azimuth_band(c.obtained);
    const auto azimuth = plot::brightest_azimuth_window(
        c.obtained, across, (across.second - across.first) / std::max(1.0f, s.farfield.zoom));
    return {.log_scale = s.farfield.log_scale,
            .altitude_deg = farfield_band(s, c.obtained),
            .azimuth_deg = azimuth,
            .only = only,
            .columns = columns};
}

void update_farfield_image(const vk::Context& ctx, WorkbenchState& s, const SceneSnapshot& snap,
                           const render::FarFieldViewOptions& o, std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 200u), h = std::max(h, 120u);
    // Redrawn when the far field or any option changes (the band follows the zoom).
    const double values[] = {double(snap.generation),
                             o.log_scale ? 1.0 : 0.0,
                             o.altitude_deg ? o.altitude_deg->first : 0.0,
                             o.altitude_deg ? o.altitude_deg->second : 0.0,
                             o.azimuth_deg ? o.azimuth_deg->first : 0.0,
                             o.azimuth_deg ? o.azimuth_deg->second : 0.0,
                             o.only ? double(*o.only) : -1.0,
                             double(o.columns)};
    const std::uint64_t generation = value_hash(values);
    if (s.farfield_image.generation == generation && s.farfield_image.width == w &&
        s.farfield_image.height == h)
        return;
    plot::Canvas cv{int(w), int(h)};
    render::draw_farfield_view(cv, {0, 0, double(w), double(h)}, snap.traced.farfield, o);
    upload(ctx, s.farfield_image, canvas_rgba(cv), w, h, generation);
}

} // namespace fird::ui
