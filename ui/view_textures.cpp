#include "view_textures.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <functional>
#include <future>
#include <span>

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
                             double(o.slope_colours),
                             double(o.curvature_colours),
                             double(s.viewport.walk_step),
                             double(s.viewport.walk_trail),
                             double(w),
                             double(h),
                             picked ? double(picked->index) : -1.0,
                             picked ? double(picked->walk.size()) : -1.0};
    return value_hash(values);
}

// Shows t's redraw when it has finished (or at once, waiting, when `wait`); the texture
// shown before becomes the next redraw's target.
void show_finished(ViewTexture& t, bool wait) {
    if (wait && t.drawing.valid()) t.drawing.wait();
    if (!t.redraw) return;
    if (wait) t.redraw->submission.wait();
    if (!t.redraw->submission.done()) return;
    ViewRedraw& r = *t.redraw;
    if (t.spare) t.retired.push_back(std::move(t.spare));
    t.spare = std::move(t.texture);
    t.texture = std::move(r.texture);
    t.generation = r.generation;
    t.key = r.key;
    t.redraw.reset(); // frees what it retired (it has finished)
}

// Whether (generation, key) is neither shown nor being drawn.
bool wanted(const ViewTexture& t, std::uint64_t generation, std::uint64_t key) {
    const bool shown = t.texture && t.generation == generation && t.key == key;
    const bool drawing =
        (t.redraw && t.redraw->generation == generation && t.redraw->key == key) ||
        (t.drawing.valid() && t.drawing_generation == generation && t.drawing_key == key);
    return !shown && !drawing;
}

// Starts a redraw into a texture of w x h (the spare one when it fits): `record` writes
// it. Only one is in flight per view: what it records (the viewport renderer's buffers,
// its render target) is free again once the one before has finished.
void start_redraw(const vk::Context& ctx, ViewTexture& t, std::uint32_t w, std::uint32_t h,
                  std::uint64_t generation, std::uint64_t key,
                  const std::function<void(VkCommandBuffer, vk::Texture&)>& record,
                  std::unique_ptr<vk::Buffer> staging, std::shared_ptr<const void> reads) {
    ViewRedraw r{.staging = std::move(staging),
                 .generation = generation,
                 .key = key,
                 .reads = std::move(reads)};
    if (t.spare && t.spare->width() == w && t.spare->height() == h)
        r.texture = std::move(t.spare);
    else
        r.texture = std::make_unique<vk::Texture>(ctx, w, h, "fird.workbench.view");
    if (t.spare) t.retired.push_back(std::move(t.spare));
    r.retired = std::move(t.retired);
    t.retired.clear();
    vk::Texture& texture = *r.texture;
    r.submission = vk::Submission(
        ctx, [&](VkCommandBuffer cb) { record(cb, texture); }, "fird.view.redraw");
    t.redraw = std::move(r);
}

} // namespace

void update_viewport_image(const vk::Context& ctx, render::ViewportRenderer& renderer,
                           WorkbenchState& s, const std::shared_ptr<const SceneSnapshot>& snapshot,
                           const PickedRay* picked, std::uint32_t w, std::uint32_t h) {
    const SceneSnapshot& snap = *snapshot;
    w = std::max(w, 64u), h = std::max(h, 64u);
    ViewTexture& t = s.viewport_image;
    show_finished(t, s.wait_for_views);
    const std::uint64_t view = camera_hash(s, picked, w, h);
    if (!wanted(t, snap.generation, view) || t.redraw) return; // the next one when it ends
    render::ViewportContent content = snap.traced.viewport;
    content.picked = picked ? std::make_optional(*picked) : std::nullopt;
    render::ViewportOptions o = s.viewport.options;
    o.camera = s.viewport.camera;
    o.walk_steps = s.viewport.walk_step + 1; // up to the current step
    o.walk_trail = s.viewport.walk_trail;
    if (!t.target || t.target->width() != w || t.target->height() != h)
        t.target = std::make_unique<render::OffscreenTarget>(ctx, w, h, "fird.workbench.viewport");
    const render::OffscreenTarget& target = *t.target;
    // Rendered on the device into the texture the panel samples: no read back.
    // The snapshot stays alive until the device has drawn its height field.
    start_redraw(
        ctx, t, w, h, snap.generation, view,
        [&](VkCommandBuffer cb, vk::Texture& tex) {
            renderer.record(cb, target, content, o);
            tex.record_copy(cb, target.colour());
        },
        nullptr, snapshot);
    if (s.wait_for_views) show_finished(t, true);
}

std::pair<double, double> farfield_band(const WorkbenchState& s,
                                        const plot::FarFieldProfiles& profiles) {
    const auto band = plot::lit_altitude_band(profiles);
    return plot::brightest_altitude_window(
        profiles, band, (band.first - band.second) / std::max(1.0f, s.farfield.zoom));
}

render::FarFieldViewOptions farfield_view_options(const WorkbenchState& s,
                                                  const SceneSnapshot& snapshot, int columns) {
    using K = render::FarFieldMapKind;
    std::optional<K> only;
    if (s.farfield.maps == 1) only = K::Desired;
    if (s.farfield.maps == 2) only = K::Obtained;
    if (s.farfield.maps == 3) only = K::Difference;
    // The zoom narrows both axes about the brightest part of the lit band (an azimuth band
    // that spans the whole circle is narrowed too: its brightest arc is shown).
    const plot::FarFieldProfiles& profiles = snapshot.obtained_profiles;
    const auto across = plot::lit_azimuth_band(profiles);
    const auto azimuth = plot::brightest_azimuth_window(
        profiles, across, (across.second - across.first) / std::max(1.0f, s.farfield.zoom));
    return {.log_scale = s.farfield.log_scale,
            .altitude_deg = farfield_band(s, profiles),
            .azimuth_deg = azimuth,
            .only = only,
            .columns = columns,
            .luminaire = s.farfield.view > 0 ? std::optional(LuminaireView(s.farfield.view - 1))
                                             : std::nullopt,
            .plane_distance_m = s.farfield.plane_distance_m};
}

void update_farfield_image(const vk::Context& ctx, WorkbenchState& s,
                           const std::shared_ptr<const SceneSnapshot>& snap,
                           const render::FarFieldViewOptions& o, std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 200u), h = std::max(h, 120u);
    ViewTexture& t = s.farfield_image;
    show_finished(t, s.wait_for_views);
    // Redrawn when the far field or any option changes (the band follows the zoom).
    const double values[] = {o.log_scale ? 1.0 : 0.0,
                             o.altitude_deg ? o.altitude_deg->first : 0.0,
                             o.altitude_deg ? o.altitude_deg->second : 0.0,
                             o.azimuth_deg ? o.azimuth_deg->first : 0.0,
                             o.azimuth_deg ? o.azimuth_deg->second : 0.0,
                             o.only ? double(*o.only) : -1.0,
                             double(o.columns),
                             o.luminaire ? double(*o.luminaire) : -1.0,
                             o.plane_distance_m,
                             double(w),
                             double(h)};
    const std::uint64_t key = value_hash(values);
    // A picture drawn on the host goes to the device once drawn (then shown when copied).
    const auto drawn = [&] {
        return t.drawing.valid() &&
               (s.wait_for_views ||
                t.drawing.wait_for(std::chrono::seconds(0)) == std::future_status::ready);
    };
    if (!t.redraw && drawn()) {
        const std::vector<std::uint8_t> rgba = t.drawing.get();
        const std::uint32_t dw = t.drawing_width, dh = t.drawing_height;
        auto staging =
            std::make_unique<vk::Buffer>(ctx, rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                         vk::MemoryUse::Upload, "fird.view.staging");
        staging->upload(ctx, std::as_bytes(std::span(rgba)));
        const vk::Buffer& pixels = *staging;
        start_redraw(
            ctx, t, dw, dh, t.drawing_generation, t.drawing_key,
            [&](VkCommandBuffer cb, vk::Texture& tex) { tex.record_upload(cb, pixels); },
            std::move(staging), nullptr);
    }
    if (wanted(t, snap->generation, key) && !t.drawing.valid()) {
        t.drawing_generation = snap->generation;
        t.drawing_key = key;
        t.drawing_width = w;
        t.drawing_height = h;
        // The snapshot is shared: the drawing thread keeps it alive.
        t.drawing = std::async(std::launch::async, [snap, o, w, h] {
            plot::Canvas cv{int(w), int(h)};
            render::draw_farfield_view(cv, {0, 0, double(w), double(h)}, snap->traced.farfield, o);
            return cv.rgba();
        });
    }
    if (s.wait_for_views) {
        show_finished(t, true);
        // Its drawing is uploaded and shown by a second pass (which starts no third).
        if (t.drawing.valid()) update_farfield_image(ctx, s, snap, o, w, h);
    }
}

} // namespace fird::ui
