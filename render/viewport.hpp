// The 3D viewport: the reflector drawn straight from the device height field, the holder,
// the light source, sample ray paths coloured by bounce, the quadtree nodes of a level as
// boxes, and one picked ray's RQRM walk (Algorithms 1-4 made visible). Everything large
// is bounded: the surface is decimated to at most 512 x 512 vertices, the quadtree level
// drawn to at most kMaxViewportBoxes nodes.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "camera.hpp"
#include "fastpath/fast_tracer.hpp"
#include "fastpath/picked_ray.hpp"
#include "fastpath/scene_params.hpp"
#include "flat_pipeline.hpp"
#include "offscreen_target.hpp"
#include "vk/buffer.hpp"
#include "vk/graphics_pipeline.hpp"

namespace fird::render {

inline constexpr std::uint32_t kMaxViewportBoxes = 16384;
inline constexpr std::uint32_t kMaxSurfaceVertices = 512;
// The curvature colours' scale: the bend radius from the flat end (dark blue) to the tight
// end (yellow), on a logarithmic scale; a press forms bends of a few millimetres at best.
inline constexpr double kCurvatureFlatRadiusMm = 1000.0, kCurvatureTightRadiusMm = 1.0;

// What the viewport shows, as compute produced it.
struct ViewportContent {
    Holder holder;
    SourceDesc source;
    const vk::Buffer* heights = nullptr;   // FastTracer::heights_buffer()
    double heights_origin_z_mm = 0;        // added to them: FastTracer::frame_origin().z
    const vk::Buffer* gradients = nullptr; // FastTracer::gradients_buffer()
    std::uint32_t width = 0, height = 0;   // of the height field
    double z_lo_mm = 0, z_hi_mm = 0;       // for the height colours
    std::vector<RayPath> paths;            // each with its rayset index
    std::vector<float> quadtree;           // FastTracer::read_quadtree() (for the level boxes)
    std::optional<PickedRay> picked;       // a ray whose path and walk are shown (picked_ray.hpp)
    // The steepest point of the reflector from the press plane (model/press_measures.hpp),
    // marked when the surface is coloured by slope.
    std::optional<glm::dvec3> steepest_mm;
    // The tightest bend (the press measures' smallest radius of curvature, 0 at a kink) and
    // its radius, marked when the surface is coloured by curvature.
    std::optional<glm::dvec3> tightest_mm;
    double min_radius_mm = 0.0;
};

struct ViewportOptions {
    OrbitCamera camera;
    bool rays = true;
    bool quadtree = false;
    std::uint32_t quadtree_level = 4; // clamped to a level of at most kMaxViewportBoxes nodes
    bool height_colours = false;
    // Coloured by the slope from the press plane instead, 0 (dark) to 90 degrees (yellow),
    // the steepest point marked: the draft a press die needs (docs/export.md).
    bool slope_colours = false;
    // Coloured by the largest principal curvature instead (the bend radius, from
    // kCurvatureFlatRadiusMm to kCurvatureTightRadiusMm), the tightest bend marked: where
    // the press's min_radius_mm binds (docs/export.md). Wins over slope colours.
    bool curvature_colours = false;
    // Steps of the picked ray's walk shown (the last of them, the current one, in red).
    std::size_t walk_steps = std::numeric_limits<std::size_t>::max();
    bool walk_trail = true; // the nodes of the steps before the current one too
    std::array<float, 4> background{0.97f, 0.97f, 0.98f, 1.0f};
};

// The level drawn for a requested one: the finest at or above it with few enough nodes.
std::uint32_t viewport_quadtree_level(const QuadtreeLayout& layout, std::uint32_t requested);

class ViewportRenderer {
  public:
    explicit ViewportRenderer(const vk::Context& ctx);
    // Records the whole view into `target` (begin and end included).
    void record(VkCommandBuffer cb, const OffscreenTarget& target, const ViewportContent& content,
                const ViewportOptions& options);

  private:
    const vk::Context* ctx_;
    vk::GraphicsPipeline surface_;
    FlatPipeline lines_, triangles_;
    vk::Buffer indices_, line_vertices_, triangle_vertices_;
    std::uint32_t index_count_ = 0, index_w_ = 0, index_h_ = 0;
};

// Colour of the segment after `bounce` reflections.
std::array<float, 4> bounce_colour(std::uint32_t bounce);

} // namespace fird::render
