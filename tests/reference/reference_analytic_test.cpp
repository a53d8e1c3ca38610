// The reference tracer against answers derived by hand.
#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {
namespace {

Scene scene(const char* name) {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + name);
}

TEST(ReferenceAnalytic, FlatTiltedMirrorGivesMirroredDirections) {
    const Scene s = scene("test/flat_mirror.toml");
    const Surface surface = Surface::make(s.reflector, s.holder);
    // z = z0 + sx x + sy y has the upward normal (-sx, -sy, 1) / |.|.
    const glm::dvec3 n = glm::normalize(glm::dvec3(-0.2, 0.1, 1.0));
    int reflected = 0;
    for (std::uint64_t i = 0; i < 20000; ++i) {
        const Ray ray = emit_ray(s.source, SamplerKind::Random, 11, i, 20000);
        std::vector<glm::dvec3> path;
        const PathResult r = trace_path(surface, s.holder, ray, 1, BouncePolicy::Strict, &path);
        if (r.fate != RayFate::FarField) continue;
        ++reflected;
        const glm::dvec3 expected = ray.direction - 2.0 * glm::dot(ray.direction, n) * n;
        ASSERT_NEAR(glm::length(r.direction - expected), 0.0, 1e-9) << "ray " << i;
        const glm::dvec3 hit = path[1];
        ASSERT_NEAR(hit.z, -2.0 + 0.2 * hit.x - 0.1 * hit.y, 1e-9) << "hit off the plane";
    }
    // About half the isotropic rays go down onto the mirror.
    EXPECT_GT(reflected, 5000);
}

TEST(ReferenceAnalytic, PointAtParaboloidFocusSendsEveryReflectedRayToTheZenith) {
    const Scene s = scene("test/focused_paraboloid.toml");
    const Surface surface = Surface::make(s.reflector, s.holder);
    const auto r = trace_reference(s.source, surface,
                                   {.rays = s.trace.rays,
                                    .seed = s.trace.seed,
                                    .max_bounces = 1,
                                    .bounce_policy = BouncePolicy::Strict,
                                    .farfield_w = 360,
                                    .farfield_h = 180});
    ASSERT_GT(r.tally.farfield, s.trace.rays / 3);
    double zenith = 0.0;
    for (std::uint32_t c = 0; c < 360; ++c)
        zenith += r.farfield.lm[c];
    EXPECT_NEAR(zenith, r.farfield.total_lm(), 1e-9 * r.farfield.total_lm());
    // And directions are exactly +z, not just within the 1-degree row.
    for (std::uint64_t i = 0; i < 5000; ++i) {
        const PathResult p =
            trace_path(surface, s.holder, emit_ray(s.source, SamplerKind::Random, 5, i, 5000), 1,
                       BouncePolicy::Strict);
        if (p.fate == RayFate::FarField) {
            ASSERT_NEAR(p.direction.z, 1.0, 1e-9);
        }
    }
}

TEST(ReferenceAnalytic, RightAngledTroughReversesTheCrossSectionAfterTwoBounces) {
    // A 90-degree V trough along y (cup with p = 1 and b = 1e12, so the y slope is 1e-12): walls z
    // = -10 + |x|. Two reflections off perpendicular walls reverse the (x, z) components.
    const Scene s = parse_scene(R"(
[source]
type = "point"
center_mm = [0.3, 0.0, 2.0]
emittance = "cosine"
axis = [0.0, 0.0, -1.0]
flux_lm = 10.0
[holder]
min_mm = [-10.0, -30.0, -10.0]
max_mm = [10.0, 30.0, 0.0]
[reflector]
family = "cup"
a = 1.0
b = 1.0e12
p = 1.0
h = 1.0
z0 = -10.0
cx = 0.0
cy = 0.0
[trace]
rays = 1000
max_bounces = 2
bounce_policy = "strict"
)",
                                "trough.toml");
    const Surface surface = Surface::make(s.reflector, s.holder);
    int two = 0;
    int total = 0;
    for (std::uint64_t i = 0; i < 20000; ++i) {
        const Ray ray = emit_ray(s.source, SamplerKind::Random, 9, i, 20000);
        const PathResult p = trace_path(surface, s.holder, ray, 2, BouncePolicy::Strict);
        if (p.fate != RayFate::FarField) continue;
        ++total;
        if (p.reflections == 1) {
            // One wall only: the mirror image in the wall x > 0 or the wall x < 0.
            const auto mirror = [&](double side) {
                const glm::dvec3 n = glm::normalize(glm::dvec3(-side, 0.0, 1.0));
                return ray.direction - 2.0 * glm::dot(ray.direction, n) * n;
            };
            const double err = std::min(glm::length(p.direction - mirror(1.0)),
                                        glm::length(p.direction - mirror(-1.0)));
            ASSERT_NEAR(err, 0.0, 1e-9) << "ray " << i;
            continue;
        }
        ASSERT_EQ(p.reflections, 2u);
        ++two;
        const glm::dvec3 expected(-ray.direction.x, ray.direction.y, -ray.direction.z);
        ASSERT_NEAR(glm::length(p.direction - expected), 0.0, 1e-9) << "ray " << i;
    }
    // Wide cosine rays often clear the far rim after one bounce; 40 % take two.
    EXPECT_GT(two, total / 4);
}

} // namespace
} // namespace fird
