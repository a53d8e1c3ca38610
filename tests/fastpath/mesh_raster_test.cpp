// The mesh raster (the paper's z-buffer step, §4.2, as a compute pass) against answers
// that do not come from it: the mesh's own height function on the host (MeshHeightField,
// double precision, point location), a plane's heights, and the higher of two planes.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "fastpath/mesh_raster.hpp"
#include "model/mesh.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

struct Raster {
    std::vector<float> heights;
    std::vector<glm::vec2> gradients;
};

Raster raster(const vk::Context& ctx, const TriangleMesh& mesh, const glm::dvec3& origin,
              const Holder& holder, std::uint32_t w, std::uint32_t h) {
    const std::uint64_t texels = std::uint64_t(w) * h;
    const vk::Buffer heights(ctx, texels * 4, vk::kStorageUsage, vk::MemoryUse::Readback,
                             "test.mesh_raster.heights");
    const vk::Buffer gradients(ctx, texels * 8, vk::kStorageUsage, vk::MemoryUse::Readback,
                               "test.mesh_raster.gradients");
    const MeshRasterizer rasterizer(ctx);
    rasterizer.rasterize(mesh, origin, holder, w, h, heights, gradients);
    return {heights.download_as<float>(ctx, texels), gradients.download_as<glm::vec2>(ctx, texels)};
}

glm::dvec2 texel_centre(const Holder& holder, std::uint32_t w, std::uint32_t h, std::uint32_t i,
                        std::uint32_t j) {
    return {holder.min_mm.x + (i + 0.5) * (holder.max_mm.x - holder.min_mm.x) / w,
            holder.min_mm.y + (j + 0.5) * (holder.max_mm.y - holder.min_mm.y) / h};
}

// A triangulated grid of nx x ny vertices over [x0, x1] x [y0, y1], heights z(x, y); its
// interior vertices moved by up to `jitter` of a cell (so edges cross texel centres at no
// pattern), each quad split along a diagonal picked at random.
template <typename Z>
TriangleMesh grid_mesh(int nx, int ny, glm::dvec2 lo, glm::dvec2 hi, Z z, double jitter,
                       std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-jitter, jitter);
    TriangleMesh m;
    const glm::dvec2 cell = (hi - lo) / glm::dvec2(nx - 1, ny - 1);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            glm::dvec2 p = lo + glm::dvec2(i, j) * cell;
            if (i > 0 && i < nx - 1) p.x += u(rng) * cell.x;
            if (j > 0 && j < ny - 1) p.y += u(rng) * cell.y;
            m.vertices.push_back({p.x, p.y, z(p.x, p.y)});
        }
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            const auto v = [&](int a, int b) { return std::uint32_t((j + b) * nx + i + a); };
            if (rng() % 2) {
                m.triangles.push_back({v(0, 0), v(1, 0), v(1, 1)});
                m.triangles.push_back({v(0, 0), v(1, 1), v(0, 1)});
            } else {
                m.triangles.push_back({v(0, 0), v(1, 0), v(0, 1)});
                m.triangles.push_back({v(1, 0), v(1, 1), v(0, 1)});
            }
        }
    return m;
}

class MeshRaster : public VulkanTest {};

// Every texel centre of a bumpy, irregularly triangulated dish, against the mesh's own
// height and face gradient computed on the host in double, with the top cut off by the
// holder (a plateau: the ceiling's height, no slope). The raster works in floats relative
// to a frame origin: heights agree to 2e-4 mm, about ten times a few float roundings of
// 50 mm coordinates times the steepest slope (about 1.5), as margin for a driver's own.
// A centre within float rounding of an edge may take either face's gradient: such texels
// must match the host's a hair to one side, and are rare.
TEST_F(MeshRaster, MatchesTheMeshsOwnHeightsAtEveryTexelCentre) {
    const auto z = [](double x, double y) {
        return 30.0 - 0.01 * (x * x + y * y) + 2.0 * std::sin(x / 7.0) * std::cos(y / 5.0);
    };
    // Reversed windings too: the raster must not care which way a face is wound.
    TriangleMesh mesh = grid_mesh(23, 17, {-40.0, -30.0}, {40.0, 30.0}, z, 0.3, 7);
    for (std::size_t k = 0; k < mesh.triangles.size(); k += 3)
        std::swap(mesh.triangles[k][1], mesh.triangles[k][2]);
    const Holder holder{{-40.0, -30.0, 0.0}, {40.0, 30.0, 30.0}};
    const glm::dvec3 origin(3.0, -2.0, 10.0);
    const std::uint32_t w = 197, h = 143;
    const MeshHeightField field(mesh, holder, "dish");
    const Raster r = raster(ctx(), mesh, origin, holder, w, h);

    std::size_t plateaus = 0, edge_gradients = 0;
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const glm::dvec2 p = texel_centre(holder, w, h, i, j);
            glm::dvec2 g;
            const auto height = field.height(p.x, p.y, &g);
            ASSERT_TRUE(height.has_value()) << i << ", " << j;
            const double expect = std::clamp(*height, holder.min_mm.z, holder.max_mm.z);
            const std::size_t t = std::size_t(j) * w + i;
            ASSERT_NEAR(r.heights[t] + origin.z, expect, 2e-4) << "texel " << i << ", " << j;
            if (*height >= holder.max_mm.z + 1e-3) {
                ++plateaus;
                EXPECT_EQ(r.gradients[t], glm::vec2(0.0f)) << "texel " << i << ", " << j;
                continue;
            }
            if (*height >= holder.max_mm.z - 1e-3) continue; // at the cut: either
            const auto same = [&](glm::dvec2 q) {
                glm::dvec2 gq;
                (void)field.height(q.x, q.y, &gq);
                return glm::length(glm::dvec2(r.gradients[t]) - gq) <= 1e-5 * (1 + glm::length(gq));
            };
            if (same(p)) continue;
            ++edge_gradients;
            const double e = 1e-4;
            EXPECT_TRUE(same(p + glm::dvec2(e, 0)) || same(p - glm::dvec2(e, 0)) ||
                        same(p + glm::dvec2(0, e)) || same(p - glm::dvec2(0, e)) ||
                        same(p + glm::dvec2(e, e)) || same(p - glm::dvec2(e, e)) ||
                        same(p + glm::dvec2(e, -e)) || same(p - glm::dvec2(e, -e)))
                << "texel " << i << ", " << j << ": a gradient of no face near it";
        }
    std::printf("%zu plateau texels, %zu on an edge\n", plateaus, edge_gradients);
    EXPECT_GT(plateaus, 100u); // the cut is exercised
    EXPECT_LT(edge_gradients, std::size_t(w) * h / 1000);

    // The same bytes again: the highest face, then the highest index, wins a texel, not
    // whichever the device ran last.
    const Raster again = raster(ctx(), mesh, origin, holder, w, h);
    EXPECT_EQ(again.heights, r.heights);
    EXPECT_EQ(again.gradients, r.gradients);
}

// A plane triangulated on the texel centres themselves, so that every edge (the
// diagonals too) runs through texel centres: a centre on an edge shared by two faces
// must be covered by one of them. A crack would read as the holder's floor.
TEST_F(MeshRaster, LeavesNoCrackWhereEdgesRunThroughTexelCentres) {
    const std::uint32_t w = 64, h = 48;
    const Holder holder{{0.0, 0.0, -5.0}, {64.0, 48.0, 50.0}}; // 1 mm texels
    const auto plane = [](double x, double y) { return 3.0 + 0.25 * x + 0.125 * y; };
    // Vertices at the centres 0.5, 4.5, ... and the outermost at the holder's edge.
    TriangleMesh mesh = grid_mesh(17, 13, {0.0, 0.0}, {64.0, 48.0}, plane, 0.0, 1);
    for (auto& v : mesh.vertices) {
        if (v.x > 0.0 && v.x < 64.0) v.x += 0.5;
        if (v.y > 0.0 && v.y < 48.0) v.y += 0.5;
        v.z = plane(v.x, v.y);
    }
    const Raster r = raster(ctx(), mesh, glm::dvec3(0.0), holder, w, h);
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const glm::dvec2 p = texel_centre(holder, w, h, i, j);
            const std::size_t t = std::size_t(j) * w + i;
            // Float: the heights (3 .. 25 mm) round at 2e-6; a few roundings.
            ASSERT_NEAR(r.heights[t], plane(p.x, p.y), 2e-5) << "texel " << i << ", " << j;
            EXPECT_EQ(r.gradients[t], glm::vec2(0.25f, 0.125f)) << "texel " << i << ", " << j;
        }
}

// Two planes crossing over the whole holder, each one triangle pair much larger than a
// work item's tile: every texel takes the higher plane and its slope.
TEST_F(MeshRaster, KeepsTheHigherOfTwoCrossingPlanes) {
    const Holder holder{{-10.0, -20.0, -100.0}, {30.0, 20.0, 100.0}};
    const auto a = [](double x, double y) { return 1.0 + 0.5 * x - 0.25 * y; };
    const auto b = [](double x, double y) { return 4.0 - 0.75 * x + 0.5 * y; };
    TriangleMesh mesh;
    const glm::dvec2 corners[] = {{-10, -20}, {30, -20}, {30, 20}, {-10, 20}};
    for (const auto& f : {+a, +b}) {
        const auto base = std::uint32_t(mesh.vertices.size());
        for (const glm::dvec2& c : corners)
            mesh.vertices.push_back({c.x, c.y, f(c.x, c.y)});
        mesh.triangles.push_back({base, base + 1, base + 2});
        mesh.triangles.push_back({base, base + 2, base + 3});
    }
    const std::uint32_t w = 300, h = 211;
    const Raster r = raster(ctx(), mesh, glm::dvec3(1.0, 2.0, 3.0), holder, w, h);
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const glm::dvec2 p = texel_centre(holder, w, h, i, j);
            const double za = a(p.x, p.y), zb = b(p.x, p.y);
            const std::size_t t = std::size_t(j) * w + i;
            // Float roundings of heights up to 40 mm and coordinates up to 30 mm.
            ASSERT_NEAR(r.heights[t] + 3.0, std::max(za, zb), 5e-5) << "texel " << i << ", " << j;
            if (std::abs(za - zb) < 1e-3) continue; // on the crossing: either slope
            EXPECT_EQ(r.gradients[t], za > zb ? glm::vec2(0.5f, -0.25f) : glm::vec2(-0.75f, 0.5f))
                << "texel " << i << ", " << j;
        }
}

// A pyramid of four large faces: most tiles lie under one face alone and are stored
// without atomics (mesh_raster_input marks them), the tiles along the ridges are shared.
// Every texel takes its face's plane, the highest where they meet.
TEST_F(MeshRaster, RastersTilesThatOneTriangleAloneReaches) {
    const Holder holder{{-30.0, -20.0, -50.0}, {30.0, 20.0, 50.0}};
    const glm::dvec3 apex(4.0, -3.0, 12.0);
    const glm::dvec2 rim[] = {{-30, -20}, {30, -20}, {30, 20}, {-30, 20}};
    TriangleMesh mesh;
    mesh.vertices.push_back(apex);
    for (const glm::dvec2& c : rim)
        mesh.vertices.push_back({c.x, c.y, 0.0});
    for (std::uint32_t k = 0; k < 4; ++k)
        mesh.triangles.push_back({0, 1 + k, 1 + (k + 1) % 4});
    const std::uint32_t w = 331, h = 217;
    const glm::dvec3 origin(0.0, 0.0, 2.0);
    const MeshRasterInput input = mesh_raster_input(
        mesh, origin, glm::dvec2(holder.min_mm - origin), glm::dvec2(holder.max_mm - origin), w, h);
    const auto sole = std::count_if(input.items.begin(), input.items.end(),
                                    [](const glm::uvec4& item) { return item.w == 1u; });
    EXPECT_GT(sole, std::ptrdiff_t(input.items.size() / 2)) << input.items.size() << " items";
    EXPECT_LT(sole, std::ptrdiff_t(input.items.size())); // and shared tiles too

    const Raster r = raster(ctx(), mesh, origin, holder, w, h);
    // Face k's plane through the apex and rim corners k, k + 1 (the pyramid is convex from
    // below: its height is the lowest of the four planes, each face's own over it).
    const auto face_plane = [&](int k, glm::dvec2 p) {
        const glm::dvec3 a = apex, b(rim[k], 0.0), c(rim[(k + 1) % 4], 0.0);
        const glm::dvec3 n = glm::cross(b - a, c - a);
        return glm::dvec3(a.z - (n.x * (p.x - a.x) + n.y * (p.y - a.y)) / n.z, -n.x / n.z,
                          -n.y / n.z);
    };
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const glm::dvec2 p = texel_centre(holder, w, h, i, j);
            glm::dvec3 lowest(1e300), second(1e300);
            for (int k = 0; k < 4; ++k) {
                const glm::dvec3 f = face_plane(k, p);
                if (f.x < lowest.x)
                    second = lowest, lowest = f;
                else if (f.x < second.x)
                    second = f;
            }
            const std::size_t t = std::size_t(j) * w + i;
            // Float roundings of heights up to 12 mm and coordinates up to 30 mm.
            ASSERT_NEAR(r.heights[t] + origin.z, lowest.x, 5e-5) << "texel " << i << ", " << j;
            if (second.x - lowest.x < 1e-3) continue; // on a ridge: either face
            EXPECT_LT(glm::length(glm::dvec2(r.gradients[t]) - glm::dvec2(lowest.y, lowest.z)),
                      1e-6)
                << "texel " << i << ", " << j;
        }
}

// Two triangles flush with the holder, rastered on the texel corners as the fast path does
// (a grid one texel larger, half a texel out: its outermost centres lie exactly on the
// mesh's rim), at sizes where a correctly rounded float sum for the last centre lands an
// ulp outside the rim (+-25 mm at 1200, +-20 at 200, ...): every corner must read the plane,
// none the floor. (lavapipe's own arithmetic lands inside at all of these; a GPU driver's
// division may not, and scripts/gpu_check.sh runs this suite there.)
TEST_F(MeshRaster, PutsTheCornersOfAMeshFlushWithTheHolderOnItsRim) {
    const auto plane = [](double x, double y) { return 5.0 + 0.1 * x - 0.2 * y; };
    for (const double a : {20.0, 25.0, 30.0, 50.0, 100.0})
        for (const std::uint32_t n : {200u, 401u, 800u, 1000u, 1200u}) {
            SCOPED_TRACE("holder +-" + std::to_string(a) + " mm, " + std::to_string(n) + " texels");
            const Holder holder{{-a, -a, -60.0}, {a, a, 60.0}};
            TriangleMesh mesh;
            for (const glm::dvec2 c : {glm::dvec2(-a, -a), {a, -a}, {a, a}, {-a, a}})
                mesh.vertices.push_back({c.x, c.y, plane(c.x, c.y)});
            mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
            const double half = a / n; // half a texel of the n-texel grid
            const Holder around{holder.min_mm - glm::dvec3(half, half, 0.0),
                                holder.max_mm + glm::dvec3(half, half, 0.0)};
            const glm::dvec3 origin(0.0, 0.0, 5.0); // the holder box's centre
            const Raster r = raster(ctx(), mesh, origin, around, n + 1, n + 1);
            std::size_t at_floor = 0;
            for (std::uint32_t j = 0; j <= n; ++j)
                for (std::uint32_t i = 0; i <= n; ++i) {
                    const double x = -a + 2.0 * a * i / n, y = -a + 2.0 * a * j / n;
                    const float z = r.heights[std::size_t(j) * (n + 1) + i];
                    at_floor += std::abs(z + origin.z - holder.min_mm.z) < 1e-3;
                    // Float: heights up to 35 mm, coordinates up to 100 mm.
                    EXPECT_NEAR(z + origin.z, plane(x, y), 5e-5) << "corner " << i << ", " << j;
                }
            EXPECT_EQ(at_floor, 0u);
        }
}

// A triangle over part of the holder only, its heights below the floor on one side and
// above the ceiling on the other, in a frame whose origin is not at z = 0: the texels it
// does not cover read the holder's floor (in the frame), the heights past the holder's z
// range are clamped to it, and both are flat.
TEST_F(MeshRaster, ReadsTheFloorWhereNothingCoversAndClampsToTheHolder) {
    const Holder holder{{0.0, 0.0, -4.0}, {40.0, 40.0, 6.0}};
    const auto plane = [](double x, double) { return -10.0 + 0.5 * x; }; // -10 .. 10 mm
    TriangleMesh mesh;
    for (const glm::dvec2 c : {glm::dvec2(0, 5), {40, 5}, {20, 35}})
        mesh.vertices.push_back({c.x, c.y, plane(c.x, c.y)});
    mesh.triangles = {{0, 1, 2}};
    const glm::dvec3 origin(20.0, 20.0, 7.0);
    const std::uint32_t n = 80;
    const Raster r = raster(ctx(), mesh, origin, holder, n, n);
    std::size_t floors = 0, ceilings = 0, slopes = 0, uncovered = 0;
    for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
            const glm::dvec2 p = texel_centre(holder, n, n, i, j);
            const std::size_t t = std::size_t(j) * n + i;
            const double z = r.heights[t] + origin.z;
            // Inside the triangle by a clear margin, outside by one, or near an edge.
            const double inside = std::min({p.y - 5.0, (35.0 - p.y) - 1.5 * std::abs(p.x - 20.0)});
            if (std::abs(inside) < 0.6) continue;
            if (inside < 0.0) {
                ++uncovered;
                EXPECT_NEAR(z, holder.min_mm.z, 1e-5) << "texel " << i << ", " << j;
                EXPECT_EQ(r.gradients[t], glm::vec2(0.0f)) << "texel " << i << ", " << j;
                continue;
            }
            const double expect = std::clamp(plane(p.x, p.y), holder.min_mm.z, holder.max_mm.z);
            EXPECT_NEAR(z, expect, 5e-5) << "texel " << i << ", " << j;
            const bool clamped =
                plane(p.x, p.y) <= holder.min_mm.z || plane(p.x, p.y) >= holder.max_mm.z;
            if (std::abs(plane(p.x, p.y) - holder.min_mm.z) < 1e-3 ||
                std::abs(plane(p.x, p.y) - holder.max_mm.z) < 1e-3)
                continue;
            floors += plane(p.x, p.y) < holder.min_mm.z;
            ceilings += plane(p.x, p.y) > holder.max_mm.z;
            slopes += !clamped;
            EXPECT_EQ(r.gradients[t], clamped ? glm::vec2(0.0f) : glm::vec2(0.5f, 0.0f))
                << "texel " << i << ", " << j;
        }
    EXPECT_GT(uncovered, 500u);
    EXPECT_GT(floors, 100u);
    EXPECT_GT(ceilings, 50u);
    EXPECT_GT(slopes, 500u);
}

// A plane reaching past the holder on every side, and triangles wholly outside it just
// beyond each edge (less than a tile away, where an empty span once made a work item that
// looped over 65535^2 texels): the holder reads the plane, the outside triangles nothing.
TEST_F(MeshRaster, IgnoresWhatLiesPastTheHolder) {
    const Holder holder{{-16.0, -16.0, -50.0}, {16.0, 16.0, 50.0}};
    const std::uint32_t n = 64; // 0.5 mm texels
    const auto plane = [](double x, double y) { return 2.0 + 0.3 * x + 0.1 * y; };
    TriangleMesh mesh;
    const auto add = [&](glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, double dz) {
        const auto k = std::uint32_t(mesh.vertices.size());
        for (const glm::dvec2& v : {a, b, c})
            mesh.vertices.push_back({v.x, v.y, plane(v.x, v.y) + dz});
        mesh.triangles.push_back({k, k + 1, k + 2});
    };
    const double o = 16.0 + 3.3 * 0.5; // 3.3 texels past each edge
    add({-o, -o}, {o, -o}, {o, o}, 0.0);
    add({-o, -o}, {o, o}, {-o, o}, 0.0);
    // 0.5 to 3.5 texels off each edge, and higher than the plane: a stray texel would show.
    for (const double d : {0.3, 1.0, 1.8}) {
        const double e = 16.0 + d;
        add({-e - 0.4, -3.0}, {-e, 2.0}, {-e - 0.2, 5.0}, 40.0);
        add({e + 0.4, -3.0}, {e, 2.0}, {e + 0.2, 5.0}, 40.0);
        add({-3.0, -e - 0.4}, {2.0, -e}, {5.0, -e - 0.2}, 40.0);
        add({-3.0, e + 0.4}, {2.0, e}, {5.0, e + 0.2}, 40.0);
    }
    const Raster r = raster(ctx(), mesh, glm::dvec3(0.0), holder, n, n);
    for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
            const glm::dvec2 p = texel_centre(holder, n, n, i, j);
            ASSERT_NEAR(r.heights[std::size_t(j) * n + i], plane(p.x, p.y), 2e-5)
                << "texel " << i << ", " << j;
        }

    // The host's layout of many small triangles scattered up to 8 texels past the low
    // edges: every work item a non-empty box of texels on the raster.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> off(-16.0 - 4.0, -16.0), along(-16.0, 16.0);
    std::uniform_real_distribution<double> jiggle(-1.5, 1.5);
    TriangleMesh scattered;
    for (int k = 0; k < 20000; ++k) {
        const bool left = k % 2 == 0;
        const glm::dvec2 c =
            left ? glm::dvec2(off(rng), along(rng)) : glm::dvec2(along(rng), off(rng));
        const auto first = std::uint32_t(scattered.vertices.size());
        for (int v = 0; v < 3; ++v) {
            glm::dvec2 q = c + glm::dvec2(jiggle(rng), jiggle(rng));
            if (left)
                q.x = std::min(q.x, -16.0 - 1e-3);
            else
                q.y = std::min(q.y, -16.0 - 1e-3);
            scattered.vertices.push_back({q.x, q.y, 1.0 + 0.01 * v});
        }
        scattered.triangles.push_back({first, first + 1, first + 2});
    }
    const MeshRasterInput input =
        mesh_raster_input(scattered, glm::dvec3(0.0), glm::dvec2(-16.0), glm::dvec2(16.0), n, n);
    for (const glm::uvec4& item : input.items) {
        const std::uint32_t x0 = item.y & 0xffffu, y0 = item.y >> 16;
        const std::uint32_t x1 = item.z & 0xffffu, y1 = item.z >> 16;
        ASSERT_TRUE(x0 < x1 && x1 <= n && y0 < y1 && y1 <= n)
            << "triangle " << item.x << ": texels [" << x0 << ", " << x1 << ") x [" << y0 << ", "
            << y1 << ")";
    }
}

} // namespace
} // namespace fird::test
