// The refined hit mode's surface and normal against the exact reference on the same rays:
// a faceted reflector comes out faceted, a ray reflected straight up lands in the zenith's
// defined column, and the paper's three models agree ray by ray within the height field's
// discretization (issue: "accuracy you can trust without reading the code").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "farfield/farfield.hpp"
#include "fastpath/fast_tracer.hpp"
#include "io/scene_file.hpp"
#include "reference/reference_tracer.hpp"
#include "stress/stress.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

constexpr double kPi = std::numbers::pi;

// A faceted bowl over the holder square [-10, 10]^2: an inverted pyramid of 24 planar
// triangles from the apex (0, 0, -6) to 24 points evenly along the square's boundary at
// z = 0 (corners included), so the mesh covers the holder rectangle and every facet is flat.
struct FacetedBowl {
    glm::dvec3 apex{0.0, 0.0, -6.0};
    std::vector<glm::dvec3> rim; // 24 boundary points, counter-clockwise

    FacetedBowl() {
        for (int k = 0; k < 24; ++k) {
            const int side = k / 6;
            const double f = -10.0 + 20.0 * (k % 6) / 6.0;
            const glm::dvec2 p = side == 0   ? glm::dvec2(f, -10.0)
                                 : side == 1 ? glm::dvec2(10.0, f)
                                 : side == 2 ? glm::dvec2(-f, 10.0)
                                             : glm::dvec2(-10.0, -f);
            rim.push_back({p.x, p.y, 0.0});
        }
    }
    // Facet k: apex, rim[k], rim[k + 1]; its upward unit normal.
    glm::dvec3 normal(int k) const {
        const glm::dvec3 n = glm::cross(rim[k] - apex, rim[(k + 1) % 24] - apex);
        return glm::normalize(n.z > 0.0 ? n : -n);
    }
    // The xy distance from p to the nearest facet edge (the apex-to-rim segments) and the
    // edge's index (between facets k - 1 and k).
    std::pair<double, int> nearest_edge(glm::dvec2 p) const {
        double best = 1e300;
        int edge = 0;
        for (int k = 0; k < 24; ++k) {
            const glm::dvec2 a(apex), b(rim[k]);
            const double t = std::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
            const double d = glm::length(p - (a + t * (b - a)));
            if (d < best) best = d, edge = k;
        }
        return {best, edge};
    }
    std::string write_obj(const std::string& path) const {
        std::ofstream out(path);
        out << fmt::format("v {} {} {}\n", apex.x, apex.y, apex.z);
        for (const glm::dvec3& v : rim)
            out << fmt::format("v {} {} {}\n", v.x, v.y, v.z);
        for (int k = 0; k < 24; ++k)
            out << fmt::format("f 1 {} {}\n", k + 2, (k + 1) % 24 + 2);
        return path;
    }
};

glm::dvec3 mirror(const glm::dvec3& d, const glm::dvec3& n) {
    return glm::normalize(d - 2.0 * glm::dot(d, n) * n);
}

double angle(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0));
}

Scene faceted_bowl_scene(const FacetedBowl& bowl, std::uint32_t bounces) {
    const std::string dir = (std::filesystem::temp_directory_path() / "fird_faceted_bowl").string();
    std::filesystem::create_directories(dir);
    Scene s;
    s.path = dir + "/faceted_bowl.toml";
    s.name = "faceted bowl";
    s.holder = {{-10.0, -10.0, -6.0}, {10.0, 10.0, 0.0}};
    s.source = {.kind = SourceKind::Point,
                .center_mm = {0.0, 0.0, -1.0},
                .emittance = Emittance::Isotropic,
                .flux_lm = 100.0};
    s.reflector.family = Family::Mesh;
    s.reflector.mesh = {.file = "faceted_bowl.obj",
                        .resolved_path = bowl.write_obj(dir + "/faceted_bowl.obj"),
                        .unit_mm = 1.0};
    s.trace.rays = 4000;
    s.trace.max_bounces = bounces;
    s.trace.hit_mode = HitMode::Refined;
    s.trace.heightfield_w = s.trace.heightfield_h = 400; // 0.05 mm texels
    s.trace.farfield_w = 360;
    s.trace.farfield_h = 180;
    validate_scene(s);
    return s;
}

// Rays from just under the holder's top at xy uniform over the square (the hits' xy are
// then near-uniform over the facets), heading down within 0.3 of the vertical.
std::vector<Ray> rays_over_the_bowl(std::size_t n) {
    std::mt19937_64 rng(2024);
    std::uniform_real_distribution<double> xy(-9.5, 9.5), tilt(-0.3, 0.3);
    std::vector<Ray> rays;
    for (std::size_t i = 0; i < n; ++i)
        rays.push_back(
            {{xy(rng), xy(rng), -0.05}, glm::normalize(glm::dvec3(tilt(rng), tilt(rng), -1.0))});
    return rays;
}

// The rays' paths on the fast path (the scene's own reflector).
std::vector<RayPath> fast_paths(const vk::Context& ctx, const Scene& s,
                                const std::vector<Ray>& rays) {
    FastTracer fast(ctx, s, 1);
    fast.set_reflector(s.reflector);
    return fast.trace_paths(rays);
}

// The bowl traced with `bounces` on the fast path, beside its exact surface.
struct BowlTrace {
    FacetedBowl bowl;
    Scene scene;
    Surface surface;
    std::vector<Ray> rays;
    std::vector<RayPath> paths;
};

BowlTrace trace_bowl(const vk::Context& ctx, std::uint32_t bounces) {
    const FacetedBowl bowl;
    Scene s = faceted_bowl_scene(bowl, bounces);
    Surface surface = Surface::make(s.reflector, s.holder);
    auto rays = rays_over_the_bowl(4000);
    auto paths = fast_paths(ctx, s, rays);
    return {bowl, std::move(s), std::move(surface), std::move(rays), std::move(paths)};
}

TEST_F(VulkanTest, AFacetedBowlReflectsAboutItsFacetsRayForRay) {
    const BowlTrace t = trace_bowl(ctx(), 1);
    const auto& [bowl, s, surface, rays, paths] = t;
    const double texel = 20.0 / 400.0, near = std::sqrt(2.0) * texel;

    // A ray reflects about the facet under its hit: the face normal is stored in float
    // (relative error 6e-8) and the reflection computed in float (a few ulps), so the
    // direction agrees with the exact one to ~1e-6 rad; 1e-5 rad bounds that with margin
    // and is far below any texel-scale error (the old blended normals erred by up to the
    // 0.2 rad between facets).
    constexpr double kFloatDirection = 1e-5;
    std::size_t near_edge = 0, far_checked = 0, adjacent = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        std::vector<glm::dvec3> v;
        const PathResult ref = trace_path(surface, s.holder, rays[i], 1, BouncePolicy::Paper, &v);
        ASSERT_EQ(ref.reflections, 1u) << "ray " << i; // every ray meets the bowl
        ASSERT_EQ(paths[i].reflections, 1u) << "ray " << i << ": no missing reflection";
        const auto [distance, edge] = bowl.nearest_edge(glm::dvec2(v[1]));
        if (distance > near) {
            ++far_checked;
            EXPECT_LT(angle(paths[i].direction, ref.direction), kFloatDirection) << "ray " << i;
            continue;
        }
        // Within a texel of a facet edge: the hit texel's centre may lie on either facet,
        // so the ray leaves along one of the two adjacent facets' mirror directions.
        ++near_edge;
        const glm::dvec3 a = mirror(rays[i].direction, bowl.normal((edge + 23) % 24));
        const glm::dvec3 b = mirror(rays[i].direction, bowl.normal(edge));
        if (std::min(angle(paths[i].direction, a), angle(paths[i].direction, b)) < kFloatDirection)
            ++adjacent;
    }
    // The share of rays within a texel diagonal of an edge: the edges' band (2 x 0.071 mm
    // wide along 24 edges of 10-14 mm) over the 19 x 19 mm square the rays fall on,
    // ~11 %, its Monte Carlo spread +-0.5 % at 4000 rays; the apex, where all 24 meet,
    // and the rim, where the square's band ends, only lower it.
    double band_mm2 = 0.0;
    for (const glm::dvec3& r : bowl.rim)
        band_mm2 += 2.0 * near * glm::length(glm::dvec2(r - bowl.apex));
    const double expected = band_mm2 / (19.0 * 19.0);
    std::printf("faceted bowl: %zu rays away from edges, %zu within a texel of one "
                "(%.2f %%, the band's area %.2f %%), %zu of them along an adjacent facet\n",
                far_checked, near_edge, 100.0 * double(near_edge) / double(rays.size()),
                100.0 * expected, adjacent);
    EXPECT_LT(double(near_edge), (expected + 0.01) * double(rays.size()));
    // Along one of the two facets but for those within a texel of the apex, where more
    // than two facets meet (24 edges in a disc of a texel: < 0.1 % of the rays), or where
    // the facet's mirror direction points into the patch the ray met (the reflection then
    // follows the patch, which never sends a ray into the surface): 2 % of them at most.
    // Normals blended across the edge (as before) put none of these rays on either facet.
    EXPECT_GE(double(adjacent), 0.98 * double(near_edge));
}

TEST_F(VulkanTest, AFacetedBowlGainsOrLosesNoReflection) {
    const BowlTrace t = trace_bowl(ctx(), 4);
    const auto& [bowl, s, surface, rays, paths] = t;
    const double near = std::sqrt(2.0) * 20.0 / 400.0;
    std::size_t compared = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        std::vector<glm::dvec3> v;
        const PathResult ref = trace_path(surface, s.holder, rays[i], 4, BouncePolicy::Paper, &v);
        // Rays whose every exact hit lies more than a texel from a facet edge and from the
        // rim (a fast hit's displacement there is float rounding): the same reflections.
        bool clear = true;
        for (std::size_t k = 1; k + 1 < v.size() && k <= ref.reflections; ++k)
            clear = clear && bowl.nearest_edge(glm::dvec2(v[k])).first > near &&
                    std::abs(v[k].x) < 10.0 - near && std::abs(v[k].y) < 10.0 - near;
        if (!clear) continue;
        ++compared;
        EXPECT_EQ(paths[i].reflections, ref.reflections) << "ray " << i;
        EXPECT_LT(angle(paths[i].direction, ref.direction), 1e-4) << "ray " << i;
    }
    EXPECT_GT(compared, 3000u);
}

TEST_F(VulkanTest, ARayReflectedStraightUpLandsInTheZenithsPhiZeroColumn) {
    Scene s = faceted_bowl_scene(FacetedBowl{}, 1);
    s.reflector.family = Family::Plane;
    s.reflector.parameters = {{"z0", -3.0}, {"sx", 0.0}, {"sy", 0.0}, {"cx", 0.0}, {"cy", 0.0}};
    std::vector<Ray> rays;
    for (int k = 0; k < 64; ++k) // straight down onto the flat mirror: reflected to +z
        rays.push_back({{-8.0 + 0.25 * k, 3.0 - 0.1 * k, -1.0}, {0.0, 0.0, -1.0}});
    FastTracer fast(ctx(), s, 1);
    fast.set_reflector(s.reflector);
    const FastRun run = fast.run_rays(rays, nullptr);
    ASSERT_EQ(run.tally.farfield, rays.size());
    const auto farfield = fast.read_farfield();
    // DESIGN.md §2: column floor((phi + pi) / 2 pi W) with phi = 0, row 0 (the zenith).
    const std::size_t zenith = s.trace.farfield_w / 2;
    EXPECT_NEAR(farfield[zenith], s.source.flux_lm, 1e-3) << "all the flux in (row 0, W / 2)";
    // The CPU binning agrees, whatever the signs of the zero components.
    for (const glm::dvec3 d : {glm::dvec3(0.0, 0.0, 1.0), glm::dvec3(-0.0, 0.0, 1.0),
                               glm::dvec3(0.0, -0.0, 1.0), glm::dvec3(-0.0, -0.0, 1.0)})
        EXPECT_EQ(farfield_cell(d, s.trace.farfield_w, s.trace.farfield_h), zenith)
            << d.x << " " << d.y;
    EXPECT_EQ(farfield_cell({-0.0, 0.0, -1.0}, 360, 180), 179u * 360u + 180u); // the nadir
}

// Model B's cup with its 5 bounces, at home and with everything moved by 1e5 mm on every
// axis: the fast path works relative to the holder's centre, so the same rays (moved) take
// the same paths. In absolute float32 coordinates a position there is rounded to 8e-3 mm
// (the old frame), which moved hits by a tenth of a 0.025 mm texel and turned directions
// by ~1e-3 rad over five bounces.
TEST_F(VulkanTest, AMultiBounceSceneFarFromTheOriginTracesAsAtHome) {
    Scene home = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/model_b.toml");
    home.reflector = target_reflector(home); // the deep cup of the paper's target
    const glm::dvec3 offset(1e5, 1e5, 1e5);
    Scene far = home;
    far.holder = {home.holder.min_mm + offset, home.holder.max_mm + offset};
    far.source.center_mm += offset;
    far.reflector.parameters["cx"] += offset.x;
    far.reflector.parameters["cy"] += offset.y;
    far.reflector.parameters["z0"] += offset.z;
    const auto rays = sample_effective_rays(home, 2000);
    std::vector<Ray> moved;
    for (const Ray& r : rays)
        moved.push_back({r.origin + offset, r.direction});
    const auto a = fast_paths(ctx(), home, rays), b = fast_paths(ctx(), far, moved);
    std::size_t multi = 0; // rays with two reflections or more
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_EQ(a[i].reflections, b[i].reflections) << "ray " << i;
        multi += a[i].reflections >= 2 ? 1 : 0;
        // Directions: float rounding of the same arithmetic (~1e-7 rad); positions: the
        // float hit point in the frame plus the double origin (1e-6 mm at 6 mm).
        EXPECT_LT(angle(a[i].direction, b[i].direction), 1e-6) << "ray " << i;
        for (std::size_t k = 1; k + 1 < a[i].vertices.size(); ++k)
            EXPECT_LT(glm::length(a[i].vertices[k] + offset - b[i].vertices[k]), 1e-5)
                << "ray " << i << " hit " << k;
    }
    std::printf("%zu of %zu rays reflected twice or more\n", multi, rays.size());
    EXPECT_GT(multi, 50u);
}

// The paper's models on the same rays through both tracers, ray by ray, with the stress
// suite's accounting (compute/stress/stress.cpp states each bound and what it bounds).
class SameRays : public VulkanTest, public ::testing::WithParamInterface<std::string> {};

TEST_P(SameRays, ModelsAgreeWithTheReferenceRayByRay) {
    Scene s = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + GetParam());
    StressCase c{.name = GetParam(), .scene = s, .sample = 2000};
    const StressResult r = run_stress_case(ctx(), c);
    std::printf("%s: tunnelled %llu spurious %llu extra %llu missing %llu (near a clamp %llu); "
                "hit p99 %.3g max %.3g texels; direction p99 %.3g max %.3g rad, %llu past %.2g\n",
                GetParam().c_str(), (unsigned long long)r.tunnelled, (unsigned long long)r.spurious,
                (unsigned long long)r.extra_reflections, (unsigned long long)r.missing_reflections,
                (unsigned long long)r.mismatches_near_clamp, r.hit_error_p99_texels,
                r.hit_error_max_texels, r.direction_error_p99_rad, r.direction_error_max_rad,
                (unsigned long long)r.direction_outliers, c.direction_tolerance_rad);
    EXPECT_TRUE(r.ok) << r.failure;
    EXPECT_EQ(r.aborted, 0u);
    EXPECT_EQ(r.nonfinite, 0u);
}

INSTANTIATE_TEST_SUITE_P(Models, SameRays,
                         ::testing::Values("model_a.toml", "model_b.toml", "model_c.toml"));

} // namespace
} // namespace fird::test
