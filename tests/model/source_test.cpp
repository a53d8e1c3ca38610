// Light-source sampling checked statistically against its analytic distributions.
#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/source.hpp"
#include "sampling/philox.hpp"

namespace fird {
namespace {

constexpr int kN = 200000;

TEST(Source, CylinderIsLambertianAboutTheOutwardNormalAndUniformAlongItsLength) {
    const SourceDesc s{.kind = SourceKind::Cylinder,
                       .center_mm = {1, 2, 3},
                       .axis = {1, 0, 0},
                       .length_mm = 4.0,
                       .radius_mm = 0.5};
    double cos_sum = 0.0, along_sq = 0.0;
    for (int i = 0; i < kN; ++i) {
        const Ray r = emit_ray(s, SamplerKind::Random, 1, std::uint64_t(i));
        const glm::dvec3 rel = r.origin - s.center_mm;
        ASSERT_NEAR(std::hypot(rel.y, rel.z), 0.5, 1e-12) << "on the lateral surface";
        ASSERT_LE(std::abs(rel.x), 2.0) << "caps are dark";
        const glm::dvec3 normal = glm::normalize(glm::dvec3(0, rel.y, rel.z));
        const double c = glm::dot(r.direction, normal);
        ASSERT_GE(c, 0.0);
        cos_sum += c;
        along_sq += rel.x * rel.x;
    }
    // Lambertian: pdf(cos) = 2 cos, E[cos] = 2/3. Uniform on [-2, 2]: E[x^2] = 4/3.
    EXPECT_NEAR(cos_sum / kN, 2.0 / 3.0, 3e-3);
    EXPECT_NEAR(along_sq / kN, 4.0 / 3.0, 1e-2);
}

TEST(Source, SphereIsUniformOnTheSurfaceAndLambertian) {
    const SourceDesc s{.kind = SourceKind::Sphere, .center_mm = {0, 0, 0}, .radius_mm = 2.0};
    glm::dvec3 mean_pos{0.0};
    double cos_sum = 0.0;
    for (int i = 0; i < kN; ++i) {
        const Ray r = emit_ray(s, SamplerKind::Sobol, 3, std::uint64_t(i));
        ASSERT_NEAR(glm::length(r.origin), 2.0, 1e-12);
        mean_pos += r.origin / double(kN);
        cos_sum += glm::dot(r.direction, r.origin / 2.0);
    }
    EXPECT_NEAR(glm::length(mean_pos), 0.0, 0.02);
    EXPECT_NEAR(cos_sum / kN, 2.0 / 3.0, 3e-3);
}

TEST(Source, IsotropicPointCoversTheSphereEvenly) {
    const SourceDesc s{.kind = SourceKind::Point, .emittance = Emittance::Isotropic};
    int up = 0;
    double z_sq = 0.0;
    for (int i = 0; i < kN; ++i) {
        const Ray r = emit_ray(s, SamplerKind::Random, 5, std::uint64_t(i));
        up += r.direction.z > 0;
        z_sq += r.direction.z * r.direction.z;
    }
    EXPECT_NEAR(double(up) / kN, 0.5, 5e-3);
    EXPECT_NEAR(z_sq / kN, 1.0 / 3.0, 3e-3); // E[z^2] = 1/3 on the unit sphere
}

TEST(Source, RaysMissingTheBoxAreDetected) {
    const Holder h{{0, 0, 0}, {1, 1, 1}};
    EXPECT_TRUE(ray_meets_box({{0.5, 0.5, 2}, {0, 0, -1}}, h));
    EXPECT_FALSE(ray_meets_box({{0.5, 0.5, 2}, {0, 0, 1}}, h)) << "behind the ray (t < 0)";
    EXPECT_FALSE(ray_meets_box({{2, 0.5, 0.5}, {0, 1, 0}}, h)) << "parallel outside the slab";
    EXPECT_TRUE(ray_meets_box({{0.5, 0.5, 0.5}, {1, 0, 0}}, h)) << "starting inside";
}

TEST(Sampling, PhiloxStreamsForNeighbouringSeedsAreUnrelated) {
    // Seed s must not replay seed s+1 shifted by one (the XOR-of-hashes failure).
    int equal = 0;
    for (std::uint64_t i = 0; i < 1000; ++i)
        equal += philox_uniforms(5, i + 1, 0)[0] == philox_uniforms(6, i, 0)[0];
    EXPECT_EQ(equal, 0);
}

} // namespace
} // namespace fird
