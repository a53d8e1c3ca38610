#include "mesh_raster.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "mesh_raster_comp.h"

namespace fird {

namespace {

// Texels [first, last]: every texel whose centre (i + 0.5, in texel units) lies less than a
// texel outside [lo, hi], so that the shader's float centres, within a hair of the host's,
// are never cut off; empty (first > last) off the grid.
std::pair<std::int64_t, std::int64_t> texel_span(double lo, double hi, std::uint32_t n) {
    // (Held near the grid first: a vertex far off it must not overflow the integers.)
    lo = std::clamp(lo, -2.0, double(n) + 2.0);
    hi = std::clamp(hi, -2.0, double(n) + 2.0);
    const auto first = std::max<std::int64_t>(0, std::int64_t(std::floor(lo - 0.5)));
    const auto last =
        std::min<std::int64_t>(std::int64_t(n) - 1, std::int64_t(std::ceil(hi - 0.5)));
    return {first, last};
}

// Whether the counter-clockwise triangle q may reach the box [lo, hi]: no edge has the
// whole box outside it. Conservative (the separating-axis test without the bounding
// boxes' axes, which the caller's tiles come near to already): a box the triangle misses
// may count as reached, never the reverse; a box that touches an edge reaches it.
bool reaches(const glm::dvec2 (&q)[3], const glm::dvec2& lo, const glm::dvec2& hi) {
    for (int k = 0; k < 3; ++k) {
        const glm::dvec2 a = q[k], b = q[(k + 1) % 3];
        const glm::dvec2 d = b - a;
        // The box's corner farthest into the edge's inner side (left of a -> b).
        const glm::dvec2 corner(d.y <= 0.0 ? hi.x : lo.x, d.x >= 0.0 ? hi.y : lo.y);
        if (d.x * (corner.y - a.y) - d.y * (corner.x - a.x) < 0.0) return false;
    }
    return true;
}

} // namespace

MeshRasterInput mesh_raster_input(const TriangleMesh& mesh, const glm::dvec3& origin,
                                  const glm::dvec2& lo, const glm::dvec2& hi, std::uint32_t width,
                                  std::uint32_t height) {
    if (width == 0 || height == 0 || width > 0xffffu || height > 0xffffu)
        throw std::invalid_argument("mesh raster: texel counts must be 1 .. 65535 a side");
    MeshRasterInput out;
    out.corners.reserve(mesh.triangles.size() * 3);
    out.items.reserve(mesh.triangles.size());
    const glm::dvec2 texels_per_mm = glm::dvec2(width, height) / (hi - lo);
    constexpr std::int64_t tile = gpu::kMeshRasterTile;
    const std::size_t tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
    std::vector<std::uint32_t> triangles_in_tile(tiles_x * tiles_y, 0);
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        // A vertical triangle covers no texel centre of a height field.
        // (Slope past 1e12, whatever the mesh's units.)
        if (n.z * n.z <= 1e-24 * glm::dot(n, n) || !std::isfinite(n.z)) continue;
        glm::vec3 p[3] = {glm::vec3(a - origin), glm::vec3(b - origin), glm::vec3(c - origin)};
        for (const glm::vec3& q : p)
            if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z))
                throw std::invalid_argument("the mesh has a vertex beyond float range");
        // The shader's orientation, from the float corners it reads (in double, where the
        // products of floats are exact): counter-clockwise seen from above.
        const double area2 = (double(p[1].x) - p[0].x) * (double(p[2].y) - p[0].y) -
                             (double(p[1].y) - p[0].y) * (double(p[2].x) - p[0].x);
        if (area2 == 0.0) continue;
        if (area2 < 0.0) std::swap(p[1], p[2]);
        const auto index = std::uint32_t(out.corners.size() / 3);
        out.corners.emplace_back(p[0], float(-n.x / n.z));
        out.corners.emplace_back(p[1], float(-n.y / n.z));
        out.corners.emplace_back(p[2], 0.0f);
        double u0 = p[0].x, u1 = p[0].x, v0 = p[0].y, v1 = p[0].y;
        for (const glm::vec3& q : p) {
            u0 = std::min(u0, double(q.x)), u1 = std::max(u1, double(q.x));
            v0 = std::min(v0, double(q.y)), v1 = std::max(v1, double(q.y));
        }
        const auto [x0, x1] =
            texel_span((u0 - lo.x) * texels_per_mm.x, (u1 - lo.x) * texels_per_mm.x, width);
        const auto [y0, y1] =
            texel_span((v0 - lo.y) * texels_per_mm.y, (v1 - lo.y) * texels_per_mm.y, height);
        if (x0 > x1 || y0 > y1) continue; // off the raster
        // The bounding box cut along the grid of tiles (the first and last tiles partial),
        // less the tiles the triangle does not reach.
        const glm::dvec2 q[3] = {{p[0].x, p[0].y}, {p[1].x, p[1].y}, {p[2].x, p[2].y}};
        for (std::int64_t ty = y0 / tile; ty <= y1 / tile; ++ty)
            for (std::int64_t tx = x0 / tile; tx <= x1 / tile; ++tx) {
                const std::int64_t xs = std::max(x0, tx * tile), ys = std::max(y0, ty * tile);
                const std::int64_t xe = std::min(x1 + 1, (tx + 1) * tile);
                const std::int64_t ye = std::min(y1 + 1, (ty + 1) * tile);
                // The tile's texels whole, not just their centres: half a texel of margin
                // is far more than the float error of a centre or an edge function, so a
                // tile the shader would find a centre of the triangle in is never cut.
                const glm::dvec2 box_lo = lo + glm::dvec2(xs, ys) / texels_per_mm;
                const glm::dvec2 box_hi = lo + glm::dvec2(xe, ye) / texels_per_mm;
                if (!reaches(q, box_lo, box_hi)) continue;
                out.items.emplace_back(index, std::uint32_t(xs | ys << 16),
                                       std::uint32_t(xe | ye << 16), 0u);
                ++triangles_in_tile[std::size_t(ty * tiles_x + tx)];
            }
    }
    if (out.corners.empty()) throw std::invalid_argument("the mesh has no non-vertical triangle");
    // A tile that one triangle alone reaches is that triangle's: its texels are stored
    // without atomics and need no second phase (most of the texels under large triangles).
    for (glm::uvec4& item : out.items) {
        const std::size_t tile_index =
            std::size_t((item.y >> 16) / tile) * tiles_x + (item.y & 0xffffu) / tile;
        item.w = triangles_in_tile[tile_index] == 1 ? 1u : 0u;
    }
    return out;
}

MeshRasterizer::MeshRasterizer(const vk::Context& ctx)
    : ctx_(&ctx), pass_(ctx, fird_spv_mesh_raster_comp, "fird.mesh_raster") {}

void MeshRasterizer::rasterize(const TriangleMesh& mesh, const glm::dvec3& origin,
                               const Holder& holder, std::uint32_t width, std::uint32_t height,
                               const vk::Buffer& heights, const vk::Buffer& gradients) const {
    const vk::Context& ctx = *ctx_;
    const glm::dvec2 lo = glm::dvec2(holder.min_mm) - glm::dvec2(origin);
    const glm::dvec2 hi = glm::dvec2(holder.max_mm) - glm::dvec2(origin);
    const MeshRasterInput input = mesh_raster_input(mesh, origin, lo, hi, width, height);
    const glm::dvec2 half_texel = (hi - lo) / glm::dvec2(width, height) / 2.0;
    const std::uint64_t texels = std::uint64_t(width) * height;
    if (input.items.size() > 0xffffffffu)
        throw std::invalid_argument("mesh raster: more tiles than a dispatch indexes");
    if (heights.size() < texels * sizeof(float) || gradients.size() < texels * 2 * sizeof(float))
        throw std::invalid_argument("mesh raster: an output holds fewer texels than the raster");

    vk::Buffer triangles(ctx, input.corners.size() * sizeof(glm::vec4), vk::kStorageUsage,
                         vk::MemoryUse::Device, "fird.mesh_raster.triangles");
    triangles.upload(ctx, std::span<const glm::vec4>(input.corners));
    vk::Buffer items(ctx, input.items.size() * sizeof(glm::uvec4), vk::kStorageUsage,
                     vk::MemoryUse::Device, "fird.mesh_raster.items");
    items.upload(ctx, std::span<const glm::uvec4>(input.items));
    const vk::Buffer height_keys(ctx, texels * sizeof(std::uint32_t), vk::kStorageUsage,
                                 vk::MemoryUse::Device, "fird.mesh_raster.height_keys");
    const vk::Buffer owners(ctx, texels * sizeof(std::uint32_t), vk::kStorageUsage,
                            vk::MemoryUse::Device, "fird.mesh_raster.owners");

    const MeshRasterBindings bindings{.triangles = vk::storage(triangles),
                                      .items = vk::storage(items),
                                      .height_keys = vk::storage(height_keys),
                                      .owners = vk::storage(owners),
                                      .heights = vk::storage(heights),
                                      .gradients = vk::storage(gradients)};
    gpu::MeshRasterPush push{
        .raster_min = {float(lo.x), float(lo.y)},
        .raster_max = {float(hi.x), float(hi.y)},
        .floor_mm = float(holder.min_mm.z - origin.z),
        .ceiling_mm = float(holder.max_mm.z - origin.z),
        .width = width,
        .height = height,
        .item_count = std::uint32_t(input.items.size()),
        .centre_min = {float(lo.x + half_texel.x), float(lo.y + half_texel.y)},
        .centre_max = {float(hi.x - half_texel.x), float(hi.y - half_texel.y)}};
    // A grid of groups no wider than every device allows (maxComputeWorkGroupCount >= 65535).
    const auto dispatch = [&](VkCommandBuffer cb, std::uint32_t phase, std::uint64_t count) {
        const std::uint64_t groups =
            (count + gpu::kMeshRasterWorkgroupSize - 1) / gpu::kMeshRasterWorkgroupSize;
        const auto x = std::uint32_t(std::clamp<std::uint64_t>(groups, 1, 65535));
        const auto y = std::uint32_t((groups + x - 1) / x);
        push.phase = phase;
        push.row_stride = x * gpu::kMeshRasterWorkgroupSize;
        pass_.dispatch(cb, bindings, push, x, std::max(y, 1u));
        vk::barrier_all(cb);
    };
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        vkCmdFillBuffer(cb, height_keys.get(), 0, VK_WHOLE_SIZE, 0);
        vkCmdFillBuffer(cb, owners.get(), 0, VK_WHOLE_SIZE, 0);
        vk::barrier_all(cb);
        dispatch(cb, gpu::kMeshRasterHeights, input.items.size());
        dispatch(cb, gpu::kMeshRasterOwners, input.items.size());
        dispatch(cb, gpu::kMeshRasterResolve, texels);
    });
}

} // namespace fird
