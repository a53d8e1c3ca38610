#include "viewport.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "surface_frag.h"
#include "surface_vert.h"

#include "model/source_outline.hpp"

namespace fird::render {

namespace {

struct SurfacePush {
    glm::mat4 view_projection;
    float grid[4];
    float shade[4];
    std::uint32_t size[4];
};

void box_edges(std::vector<FlatVertex>& out, const glm::dvec3& lo, const glm::dvec3& hi,
               const std::array<float, 4>& c) {
    const auto corner = [&](int k) {
        return glm::vec3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
    };
    static constexpr int kEdges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                                          {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    for (const auto& e : kEdges)
        for (int k : e) {
            const glm::vec3 p = corner(k);
            out.push_back({{p.x, p.y, p.z}, {c[0], c[1], c[2], c[3]}});
        }
}

// A node's box: its texels' xy extent, from the holder's floor to its maximum height.
std::pair<glm::dvec3, glm::dvec3> node_box(const Holder& h, std::uint32_t w, std::uint32_t hh,
                                           std::uint32_t level, std::uint32_t x, std::uint32_t y,
                                           double top) {
    const double dx = (h.max_mm.x - h.min_mm.x) / w, dy = (h.max_mm.y - h.min_mm.y) / hh;
    const std::uint32_t s = 1u << level;
    return {{h.min_mm.x + x * s * dx, h.min_mm.y + y * s * dy, h.min_mm.z},
            {h.min_mm.x + std::min((x + 1) * s, w) * dx,
             h.min_mm.y + std::min((y + 1) * s, hh) * dy, std::max(top, h.min_mm.z)}};
}

void upload(const vk::Context& ctx, vk::Buffer& buffer, const std::vector<FlatVertex>& v,
            const char* name) {
    const std::size_t bytes = std::max<std::size_t>(v.size(), 1) * sizeof(FlatVertex);
    if (buffer.size() < bytes)
        buffer =
            vk::Buffer(ctx, bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, vk::MemoryUse::Upload, name);
    if (!v.empty()) buffer.upload(ctx, std::span<const FlatVertex>(v));
}

} // namespace

std::array<float, 4> bounce_colour(std::uint32_t b) {
    static constexpr std::array<float, 4> kColours[] = {
        {0.95f, 0.65f, 0.10f, 0.9f}, {0.85f, 0.20f, 0.15f, 0.9f}, {0.20f, 0.45f, 0.85f, 0.9f},
        {0.20f, 0.65f, 0.30f, 0.9f}, {0.55f, 0.25f, 0.65f, 0.9f}, {0.10f, 0.60f, 0.65f, 0.9f},
        {0.45f, 0.45f, 0.45f, 0.9f}};
    return kColours[std::min<std::size_t>(b, std::size(kColours) - 1)];
}

std::uint32_t viewport_quadtree_level(const QuadtreeLayout& q, std::uint32_t requested) {
    std::uint32_t l = std::min(requested, q.levels - 1);
    while (l + 1 < q.levels && std::uint64_t(q.w[l]) * q.h[l] > kMaxViewportBoxes)
        ++l;
    return l;
}

ViewportRenderer::ViewportRenderer(const vk::Context& ctx)
    : ctx_(&ctx), lines_(ctx, VK_PRIMITIVE_TOPOLOGY_LINE_LIST, "fird.viewport.lines"),
      triangles_(ctx, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, "fird.viewport.triangles") {
    const VkVertexInputBindingDescription bindings[] = {
        {.binding = 0, .stride = 4, .inputRate = VK_VERTEX_INPUT_RATE_VERTEX},
        {.binding = 1, .stride = 8, .inputRate = VK_VERTEX_INPUT_RATE_VERTEX}};
    const VkVertexInputAttributeDescription attributes[] = {
        {.location = 0, .binding = 0, .format = VK_FORMAT_R32_SFLOAT},
        {.location = 1, .binding = 1, .format = VK_FORMAT_R32G32_SFLOAT}};
    const VkFormat colour_format = kColourFormat;
    surface_ = vk::make_graphics_pipeline(
        ctx, {.vertex_spirv = fird_spv_surface_vert,
              .fragment_spirv = fird_spv_surface_frag,
              .push_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
              .push_bytes = sizeof(SurfacePush),
              .attributes = attributes,
              .bindings = bindings,
              .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
              .depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL,
              .colour_formats = std::span(&colour_format, 1),
              .depth_format = kDepthFormat,
              .blend = {.blendEnable = VK_FALSE,
                        .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                          VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT},
              .name = "fird.viewport.surface"});
}

void ViewportRenderer::record(VkCommandBuffer cb, const OffscreenTarget& target,
                              const ViewportContent& c, const ViewportOptions& o) {
    const double aspect = double(target.width()) / target.height();
    const glm::mat4 vp = view_projection(o.camera, aspect);
    std::array<float, 16> transform;
    std::copy(&vp[0][0], &vp[0][0] + 16, transform.begin());

    // The surface's index grid, decimated to at most kMaxSurfaceVertices a side; made
    // once per height-field size.
    if (c.heights && (index_w_ != c.width || index_h_ != c.height)) {
        const std::uint32_t sx =
            std::max(1u, (c.width + kMaxSurfaceVertices - 1) / kMaxSurfaceVertices);
        const std::uint32_t sy =
            std::max(1u, (c.height + kMaxSurfaceVertices - 1) / kMaxSurfaceVertices);
        std::vector<std::uint32_t> cols, rows, idx;
        for (std::uint32_t i = 0; i < c.width; i += sx)
            cols.push_back(i);
        if (cols.back() != c.width - 1) cols.push_back(c.width - 1);
        for (std::uint32_t j = 0; j < c.height; j += sy)
            rows.push_back(j);
        if (rows.back() != c.height - 1) rows.push_back(c.height - 1);
        for (std::size_t b = 0; b + 1 < rows.size(); ++b)
            for (std::size_t a = 0; a + 1 < cols.size(); ++a) {
                const auto v = [&](std::size_t i, std::size_t j) {
                    return rows[j] * c.width + cols[i];
                };
                for (std::uint32_t k :
                     {v(a, b), v(a + 1, b), v(a + 1, b + 1), v(a, b), v(a + 1, b + 1), v(a, b + 1)})
                    idx.push_back(k);
            }
        indices_ = vk::Buffer(*ctx_, std::max<std::size_t>(idx.size(), 1) * 4,
                              VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              vk::MemoryUse::Device, "fird.viewport.surface.indices");
        indices_.upload(*ctx_, std::span<const std::uint32_t>(idx));
        index_count_ = std::uint32_t(idx.size());
        index_w_ = c.width;
        index_h_ = c.height;
    }

    std::vector<FlatVertex> lines, triangles;
    box_edges(lines, c.holder.min_mm, c.holder.max_mm, {0.35f, 0.35f, 0.40f, 1.0f});
    // The source (its shape, in warm white).
    {
        const SourceDesc& s = c.source;
        const std::array<float, 4> col{1.0f, 0.85f, 0.35f, 1.0f};
        const SourceOutline outline =
            source_outline(s, 0.01 * glm::length(c.holder.max_mm - c.holder.min_mm));
        for (const auto& t : outline.triangles)
            for (const std::uint32_t i : t) {
                const glm::dvec3& p = outline.vertices_mm[i];
                triangles.push_back(
                    {{float(p.x), float(p.y), float(p.z)}, {col[0], col[1], col[2], col[3]}});
            }
    }
    // A path's segments, coloured by the reflections before each (or all in `colour`).
    const auto segments = [&](const RayPath& p, float alpha,
                              const std::optional<std::array<float, 4>>& colour) {
        for (std::size_t k = 0; k + 1 < p.vertices.size(); ++k) {
            auto col = colour.value_or(bounce_colour(std::uint32_t(k)));
            col[3] = std::min(col[3], alpha);
            for (const glm::dvec3& v : {p.vertices[k], p.vertices[k + 1]})
                lines.push_back(
                    {{float(v.x), float(v.y), float(v.z)}, {col[0], col[1], col[2], col[3]}});
        }
    };
    if (o.rays)
        for (const RayPath& p : c.paths)
            if (!c.picked || p.ray_index != c.picked->index) // the picked one: below, in black
                segments(p, c.picked ? 0.35f : 1.0f, std::nullopt);
    if (c.picked) segments(c.picked->path, 1.0f, std::array<float, 4>{0.05f, 0.05f, 0.05f, 1.0f});
    const QuadtreeLayout q = quadtree_layout(std::max(c.width, 1u), std::max(c.height, 1u));
    if (o.quadtree && !c.quadtree.empty()) {
        const std::uint32_t l = viewport_quadtree_level(q, o.quadtree_level);
        for (std::uint32_t y = 0; y < q.h[l]; ++y)
            for (std::uint32_t x = 0; x < q.w[l]; ++x) {
                const float top = c.quadtree[q.offset[l] + std::size_t(y) * q.w[l] + x];
                const auto [lo, hi] = node_box(c.holder, c.width, c.height, l, x, y, top);
                box_edges(lines, lo, hi, {0.25f, 0.45f, 0.75f, 0.45f});
            }
    }
    // The picked ray's walk, node by node, coarse (light) to fine (dark); the current step
    // (the last shown) in red, with a cross where the ray is at its t.
    const std::vector<WalkStep> no_walk;
    const std::vector<WalkStep>& walk = c.picked ? c.picked->walk : no_walk;
    const std::size_t steps = std::min(o.walk_steps, walk.size());
    for (std::size_t k = o.walk_trail ? 0 : std::max<std::size_t>(steps, 1) - 1; k < steps; ++k) {
        const WalkStep& s = walk[k];
        const auto [lo, hi] =
            node_box(c.holder, c.width, c.height, s.level, s.x, s.y, s.max_height_mm);
        const float shade = 0.15f + 0.6f * float(s.level) / float(std::max(1u, q.levels - 1));
        const bool last = k + 1 == steps;
        box_edges(lines, lo, hi,
                  last ? std::array<float, 4>{0.9f, 0.1f, 0.1f, 1.0f}
                       : std::array<float, 4>{shade, 0.2f + 0.5f * shade, 0.2f, 0.8f});
        const auto& v = c.picked->path.vertices;
        if (last && s.bounce + 1 < v.size()) {
            const glm::dvec3 at =
                v[s.bounce] + double(s.t) * glm::normalize(v[s.bounce + 1] - v[s.bounce]);
            const double r = 0.01 * glm::length(c.holder.max_mm - c.holder.min_mm);
            for (int axis = 0; axis < 3; ++axis) {
                glm::dvec3 d(0.0);
                d[axis] = r;
                box_edges(lines, at - d, at + d, {0.9f, 0.1f, 0.1f, 1.0f});
            }
        }
    }
    // The steepest point when coloured by slope, the tightest bend when coloured by
    // curvature: a magenta cross a fiftieth of the holder wide, raised by half its arm so
    // that the surface through its centre does not hide it (a bowl's apex seen from above).
    const std::optional<glm::dvec3>& marked = o.curvature_colours ? c.tightest_mm
                                              : o.slope_colours   ? c.steepest_mm
                                                                  : std::nullopt;
    if (marked) {
        const double r = 0.02 * glm::length(c.holder.max_mm - c.holder.min_mm);
        for (int axis = 0; axis < 3; ++axis) {
            glm::dvec3 d(0.0);
            d[axis] = r;
            const glm::dvec3 centre = *marked + glm::dvec3(0.0, 0.0, 0.5 * r);
            box_edges(lines, centre - d, centre + d, {0.95f, 0.15f, 0.55f, 1.0f});
        }
    }
    upload(*ctx_, line_vertices_, lines, "fird.viewport.line_vertices");
    upload(*ctx_, triangle_vertices_, triangles, "fird.viewport.triangle_vertices");

    target.begin(cb, o.background);
    if (c.heights && index_count_ > 0) {
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_.pipeline.get());
        const VkBuffer vbs[] = {c.heights->get(), c.gradients->get()};
        const VkDeviceSize offsets[] = {0, 0};
        vkCmdBindVertexBuffers(cb, 0, 2, vbs, offsets);
        vkCmdBindIndexBuffer(cb, indices_.get(), 0, VK_INDEX_TYPE_UINT32);
        const Holder& h = c.holder;
        // The colour scale's ends: heights, or (curvature) log10 of the curvatures in 1/mm.
        const bool bends = o.curvature_colours;
        SurfacePush push{
            .view_projection = vp,
            .grid = {float(h.min_mm.x), float(h.min_mm.y),
                     float((h.max_mm.x - h.min_mm.x) / c.width),
                     float((h.max_mm.y - h.min_mm.y) / c.height)},
            .shade = {bends ? float(-std::log10(kCurvatureFlatRadiusMm)) : float(c.z_lo_mm),
                      bends ? float(-std::log10(kCurvatureTightRadiusMm)) : float(c.z_hi_mm),
                      bends              ? 3.0f
                      : o.slope_colours  ? 2.0f
                      : o.height_colours ? 1.0f
                                         : 0.0f,
                      float(c.heights_origin_z_mm)},
            .size = {c.width, c.height, 0, 0}};
        vkCmdPushConstants(cb, surface_.layout.get(),
                           VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof(push), &push);
        vkCmdDrawIndexed(cb, index_count_, 1, 0, 0, 0);
    }
    triangles_.draw(cb, triangle_vertices_, std::uint32_t(triangles.size()), transform);
    lines_.draw(cb, line_vertices_, std::uint32_t(lines.size()), transform);
    target.end(cb);
}

} // namespace fird::render
