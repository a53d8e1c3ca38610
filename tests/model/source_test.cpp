// Light-source sampling checked statistically against its analytic distributions.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "model/emission_table.hpp"
#include "model/source.hpp"
#include "photometry/photometry_file.hpp"
#include "sampling/philox.hpp"
#include "sampling/strata.hpp"

namespace fird {
namespace {

constexpr int kN = 200000;

// The cylinder samples its direction first, then the point (emitter.h): still uniform on
// the lateral surface and Lambertian about the outward normal, with every sampler.
TEST(Source, CylinderIsLambertianAboutTheOutwardNormalAndUniformOnItsSurface) {
    const SourceDesc s{.kind = SourceKind::Cylinder,
                       .center_mm = {1, 2, 3},
                       .axis = {1, 0, 0},
                       .length_mm = 4.0,
                       .radius_mm = 0.5};
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Random, SamplerKind::Sobol}) {
        SCOPED_TRACE(sampler_name(sampler));
        double cos_sum = 0.0, cos_sq = 0.0, along_sq = 0.0, axial_sq = 0.0;
        glm::dvec2 mean_normal{0.0};
        double normal_y_sq = 0.0;
        for (int i = 0; i < kN; ++i) {
            const Ray r = emit_ray(s, sampler, 1, std::uint64_t(i), kN);
            const glm::dvec3 rel = r.origin - s.center_mm;
            ASSERT_NEAR(std::hypot(rel.y, rel.z), 0.5, 1e-12) << "on the lateral surface";
            ASSERT_LE(std::abs(rel.x), 2.0) << "caps are dark";
            ASSERT_NEAR(glm::length(r.direction), 1.0, 1e-12);
            const glm::dvec3 normal = glm::normalize(glm::dvec3(0, rel.y, rel.z));
            const double c = glm::dot(r.direction, normal);
            ASSERT_GE(c, 0.0) << "leaves outwards";
            cos_sum += c;
            cos_sq += c * c;
            along_sq += rel.x * rel.x;
            axial_sq += r.direction.x * r.direction.x;
            mean_normal += glm::dvec2(normal.y, normal.z) / double(kN);
            normal_y_sq += normal.y * normal.y;
        }
        // Lambertian: pdf(cos) = 2 cos, E[cos] = 2/3, E[cos^2] = 1/2. Uniform on [-2, 2]:
        // E[x^2] = 4/3. Uniform around the axis: the mean normal 0, E[n_y^2] = 1/2. The
        // intensity of a Lambertian cylinder goes as the sine of the angle to its axis, so
        // the direction's cosine c to the axis has the density (2 / pi) sqrt(1 - c^2):
        // E[c^2] = 1/4. The bounds, in standard errors of independent rays (the stratified
        // sampler does not raise them): E[cos] 5.7 (sd sqrt(1/18 / N) = 5.3e-4),
        // E[cos^2] 4.6 (sqrt(1/12 / N)), E[x^2] 3.7 (sqrt(64/45 / N) = 2.7e-3), each mean
        // normal component 4.5 (sqrt(1/2 / N) = 1.6e-3), E[n_y^2] 3.8 (sqrt(1/8 / N)),
        // E[c^2] 5.4 (sqrt(1/16 / N)).
        EXPECT_NEAR(cos_sum / kN, 2.0 / 3.0, 3e-3);
        EXPECT_NEAR(cos_sq / kN, 0.5, 3e-3);
        EXPECT_NEAR(along_sq / kN, 4.0 / 3.0, 1e-2);
        EXPECT_NEAR(mean_normal.x, 0.0, 7.2e-3);
        EXPECT_NEAR(mean_normal.y, 0.0, 7.2e-3);
        EXPECT_NEAR(normal_y_sq / kN, 0.5, 3e-3);
        EXPECT_NEAR(axial_sq / kN, 0.25, 3e-3);
    }
}

// The sphere samples its direction first, then the point: still uniform on the surface
// and Lambertian about the outward normal, with every sampler.
TEST(Source, SphereIsUniformOnTheSurfaceAndLambertian) {
    const SourceDesc s{.kind = SourceKind::Sphere, .center_mm = {0, 0, 0}, .radius_mm = 2.0};
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Random, SamplerKind::Sobol}) {
        SCOPED_TRACE(sampler_name(sampler));
        glm::dvec3 mean_pos{0.0};
        double cos_sum = 0.0, cos_sq = 0.0, pos_z_sq = 0.0;
        for (int i = 0; i < kN; ++i) {
            const Ray r = emit_ray(s, sampler, 3, std::uint64_t(i), kN);
            ASSERT_NEAR(glm::length(r.origin), 2.0, 1e-12);
            ASSERT_NEAR(glm::length(r.direction), 1.0, 1e-12);
            mean_pos += r.origin / double(kN);
            const double c = glm::dot(r.direction, r.origin / 2.0);
            ASSERT_GE(c, 0.0) << "leaves outwards";
            cos_sum += c;
            cos_sq += c * c;
            pos_z_sq += r.origin.z * r.origin.z / 4.0;
        }
        EXPECT_NEAR(glm::length(mean_pos), 0.0, 0.02);
        // Lambertian: pdf(cos) = 2 cos, E[cos] = 2/3, E[cos^2] = 1/2; uniform: E[z^2] = 1/3.
        EXPECT_NEAR(cos_sum / kN, 2.0 / 3.0, 3e-3);
        EXPECT_NEAR(cos_sq / kN, 0.5, 3e-3);
        EXPECT_NEAR(pos_z_sq / kN, 1.0 / 3.0, 3e-3);
    }
}

TEST(Source, IsotropicPointCoversTheSphereEvenly) {
    const SourceDesc s{.kind = SourceKind::Point, .emittance = Emittance::Isotropic};
    int up = 0;
    double z_sq = 0.0;
    for (int i = 0; i < kN; ++i) {
        const Ray r = emit_ray(s, SamplerKind::Random, 5, std::uint64_t(i), kN);
        up += r.direction.z > 0;
        z_sq += r.direction.z * r.direction.z;
    }
    EXPECT_NEAR(double(up) / kN, 0.5, 5e-3);
    EXPECT_NEAR(z_sq / kN, 1.0 / 3.0, 3e-3); // E[z^2] = 1/3 on the unit sphere
}

// A disk and a rectangle, tilted and turned: one-sided Lambertian about the normal,
// uniform over the area, in the frame (x_axis, normal x x_axis, normal).
TEST(Source, DiskAndRectangleAreOneSidedLambertianAndUniformOverTheirArea) {
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.4, -0.3, -1.0));
    const glm::dvec3 x = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), n));
    const glm::dvec3 y = glm::cross(n, x);
    const SourceDesc disk{
        .kind = SourceKind::Disk, .center_mm = {1, 2, 3}, .axis = n, .x_axis = x, .radius_mm = 2.0};
    const SourceDesc rectangle{.kind = SourceKind::Rectangle,
                               .center_mm = {1, 2, 3},
                               .axis = n,
                               .x_axis = x,
                               .width_mm = 6.0,
                               .height_mm = 1.0};
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Random, SamplerKind::Sobol})
        for (const SourceDesc& s : {disk, rectangle}) {
            SCOPED_TRACE(fmt::format("{}, {}", s.kind == SourceKind::Disk ? "disk" : "rectangle",
                                     sampler_name(sampler)));
            double cos_sum = 0.0, cos_sq = 0.0, x_sq = 0.0, y_sq = 0.0, r_sq = 0.0;
            glm::dvec3 mean{0.0};
            for (int i = 0; i < kN; ++i) {
                const Ray r = emit_ray(s, sampler, 2, std::uint64_t(i), kN);
                const glm::dvec3 rel = r.origin - s.center_mm;
                ASSERT_NEAR(glm::dot(rel, n), 0.0, 1e-12) << "in the emitter's plane";
                ASSERT_NEAR(glm::length(r.direction), 1.0, 1e-12);
                const double c = glm::dot(r.direction, n);
                ASSERT_GE(c, 0.0) << "one-sided: out of the emitting face only";
                const double px = glm::dot(rel, x), py = glm::dot(rel, y);
                if (s.kind == SourceKind::Disk) {
                    ASSERT_LE(std::hypot(px, py), 2.0 + 1e-12);
                } else {
                    ASSERT_LE(std::abs(px), 3.0 + 1e-12);
                    ASSERT_LE(std::abs(py), 0.5 + 1e-12);
                }
                cos_sum += c;
                cos_sq += c * c;
                x_sq += px * px;
                y_sq += py * py;
                r_sq += px * px + py * py;
                mean += rel / double(kN);
            }
            // Lambertian: E[cos] = 2/3, E[cos^2] = 1/2. Uniform over a disk of radius R:
            // E[r^2] = R^2 / 2; over a w x h rectangle: E[x^2] = w^2 / 12, E[y^2] = h^2 / 12.
            EXPECT_NEAR(cos_sum / kN, 2.0 / 3.0, 3e-3);
            EXPECT_NEAR(cos_sq / kN, 0.5, 3e-3);
            EXPECT_NEAR(glm::length(mean), 0.0, 0.02);
            if (s.kind == SourceKind::Disk) {
                EXPECT_NEAR(r_sq / kN, 2.0, 0.02);
                EXPECT_NEAR(x_sq / kN, y_sq / kN, 0.02) << "round, not stretched";
            } else {
                EXPECT_NEAR(x_sq / kN, 3.0, 0.03);
                EXPECT_NEAR(y_sq / kN, 1.0 / 12.0, 1e-3);
            }
        }
}

// Where no x_axis is given, world +x made perpendicular to the normal (or +y where the
// normal lies near the x axis): unit, perpendicular, and +x itself for a level emitter.
TEST(Source, TheDefaultXAxisIsPerpendicularToTheNormal) {
    for (const glm::dvec3& n : {glm::dvec3(0, 0, 1), glm::dvec3(0, 0, -1), glm::dvec3(1, 0, 0),
                                glm::dvec3(-0.3, 0.8, 0.1), glm::dvec3(0.95, 0.1, 0.0)}) {
        const glm::dvec3 x = default_x_axis(n);
        EXPECT_NEAR(glm::length(x), 1.0, 1e-12);
        EXPECT_NEAR(glm::dot(x, glm::normalize(n)), 0.0, 1e-12);
    }
    EXPECT_NEAR(glm::length(default_x_axis({0, 0, -1}) - glm::dvec3(1, 0, 0)), 0.0, 1e-12);
}

// A photometric source emits its file's distribution, turned by normal and x_axis: the
// share of rays in each 10-degree gamma band and 45-degree C sector is the share of the
// file's flux there (its intensity interpolated as photometry/candela_table.hpp states),
// integrated here by the midpoint rule over intensity_cd, not through the emitter's
// table; within 4.5 binomial sigma for each of the 72 cells. The file (an independent,
// hand-made one) is I = 100 (1 + 0.3 cos C + 0.3 sin C) cos(gamma) cd up to gamma = 90
// degrees: no mirror symmetry in C, so a C turned the wrong way round fails.
TEST(Source, APhotometricSourceEmitsItsFilesDistribution) {
    const CandelaTable table = read_photometry(
        std::string(FIRD_SOURCE_DIR) + "/tests/photometry/data/lm63_2002_asymmetric_emitter.ies");
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, 0.1, 1.0));
    const glm::dvec3 x = default_x_axis(n);
    const glm::dvec3 y = glm::cross(n, x);
    SourceDesc s{.kind = SourceKind::Photometric, .center_mm = {1, 2, 3}, .axis = n, .x_axis = x};
    s.table = emission_table(table);
    constexpr int kBands = 9, kSectors = 8;
    const double deg = std::numbers::pi / 180.0;
    std::vector<double> expected(kBands * kSectors, 0.0);
    double total = 0.0;
    constexpr int kSteps = 60; // per band in cos(gamma) and per sector in C
    for (int b = 0; b < kBands; ++b)
        for (int k = 0; k < kSectors; ++k) {
            const double mu0 = std::cos(10.0 * b * deg), mu1 = std::cos(10.0 * (b + 1) * deg);
            double sum = 0.0;
            for (int i = 0; i < kSteps; ++i)
                for (int j = 0; j < kSteps; ++j) {
                    const double mu = mu0 + (mu1 - mu0) * (i + 0.5) / kSteps;
                    const double c = 45.0 * k + 45.0 * (j + 0.5) / kSteps;
                    sum += intensity_cd(table, c, std::acos(mu) / deg);
                }
            expected[std::size_t(b * kSectors + k)] =
                sum * (mu0 - mu1) * 45.0 * deg / kSteps / kSteps;
            total += expected[std::size_t(b * kSectors + k)];
        }
    EXPECT_NEAR(total, integrated_flux_lm(table), 1e-6 * total) << "the bands cover the flux";
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Random}) {
        SCOPED_TRACE(sampler_name(sampler));
        std::vector<double> count(kBands * kSectors, 0.0);
        for (int i = 0; i < kN; ++i) {
            const Ray r = emit_ray(s, sampler, 8, std::uint64_t(i), kN);
            ASSERT_NEAR(glm::length(r.origin - s.center_mm), 0.0, 1e-12) << "a point source";
            const glm::dvec3 d{glm::dot(r.direction, x), glm::dot(r.direction, y),
                               glm::dot(r.direction, n)};
            const double gamma = std::acos(std::clamp(-d.z, -1.0, 1.0)) / deg;
            double c = std::atan2(d.y, d.x) / deg;
            if (c < 0.0) c += 360.0;
            ASSERT_LE(gamma, 90.0 + 1e-6) << "no light above the horizon";
            const int b = std::min(kBands - 1, int(gamma / 10.0));
            const int k = std::min(kSectors - 1, int(c / 45.0));
            count[std::size_t(b * kSectors + k)] += 1.0;
        }
        for (std::size_t cell = 0; cell < count.size(); ++cell) {
            const double p = expected[cell] / total;
            EXPECT_NEAR(count[cell], p * kN, 4.5 * std::sqrt(kN * p * (1 - p)) + 1.0)
                << "band " << cell / kSectors << ", sector " << cell % kSectors;
        }
    }
}

TEST(Source, RaysMissingTheBoxAreDetected) {
    const Holder h{{0, 0, 0}, {1, 1, 1}};
    EXPECT_TRUE(ray_meets_box({{0.5, 0.5, 2}, {0, 0, -1}}, h));
    EXPECT_FALSE(ray_meets_box({{0.5, 0.5, 2}, {0, 0, 1}}, h)) << "behind the ray (t < 0)";
    EXPECT_FALSE(ray_meets_box({{2, 0.5, 0.5}, {0, 1, 0}}, h)) << "parallel outside the slab";
    EXPECT_TRUE(ray_meets_box({{0.5, 0.5, 0.5}, {1, 0, 0}}, h)) << "starting inside";
}

// Stratified sampling: ray i of N lies in stratum floor((i K + s) / N), never before its
// predecessor's, and every one of the K strata holds N / K rays give or take two; inside
// its cell a ray is uniform, and the last two dimensions are plain uniforms.
TEST(Sampling, StratifiedRaysVisitEveryStratumInOrderAndEvenly) {
    constexpr std::uint64_t kRays = 3 * kStrata + 12345; // not a multiple of the strata
    std::vector<std::uint32_t> count(kStrata, 0);
    std::uint32_t previous = 0;
    double sum[4] = {}, offset_sum = 0.0;
    for (std::uint64_t i = 0; i < kRays; ++i) {
        const std::array<double, 4> u = stratified_uniforms(9, i, kRays);
        for (int k = 0; k < 4; ++k) {
            ASSERT_GT(u[k], 0.0);
            ASSERT_LT(u[k], 1.0);
            sum[k] += u[k];
        }
        const double cells = double(1u << gpu::kStratumBits);
        const auto qx = std::uint32_t(u[0] * cells), qy = std::uint32_t(u[1] * cells);
        std::uint32_t c = 0; // Morton index, written out here
        for (std::uint32_t b = 0; b < gpu::kStratumBits; ++b)
            c |= (((qx >> b) & 1u) << (2 * b)) | (((qy >> b) & 1u) << (2 * b + 1));
        ASSERT_GE(c, previous) << "ray " << i;
        previous = c;
        ++count[c];
        offset_sum += u[0] * cells - double(qx);
    }
    const double share = double(kRays) / double(kStrata);
    for (std::uint32_t c = 0; c < kStrata; ++c)
        ASSERT_NEAR(double(count[c]), share, 2.0) << "stratum " << c; // independent: up to 9
    for (int k = 0; k < 4; ++k)
        EXPECT_NEAR(sum[k] / double(kRays), 0.5, 2e-3) << "dimension " << k;
    EXPECT_NEAR(offset_sum / double(kRays), 0.5, 3e-3) << "uniform inside the cell";
}

// A sphere's, a cylinder's, a point's and a disk's rays come out of the stratified sampler
// in direction order (rayset.comp keeps that order instead of sorting).
TEST(Sampling, StratifiedRaysOfTheShapedSourcesComeInDirectionOrder) {
    const auto mean_turn_deg = [](const SourceDesc& s, SamplerKind sampler) {
        double sum = 0.0;
        glm::dvec3 previous = emit_ray(s, sampler, 4, 0, kN).direction;
        for (int i = 1; i < kN; ++i) {
            const glm::dvec3 d = emit_ray(s, sampler, 4, std::uint64_t(i), kN).direction;
            sum += std::acos(std::clamp(glm::dot(d, previous), -1.0, 1.0));
            previous = d;
        }
        return sum / (kN - 1) * 180.0 / std::numbers::pi;
    };
    const SourceDesc sphere{.kind = SourceKind::Sphere, .radius_mm = 1.0};
    const SourceDesc point{.kind = SourceKind::Point, .emittance = Emittance::Isotropic};
    const SourceDesc cosine{.kind = SourceKind::Point, .axis = {0, 0, -1}};
    const SourceDesc disk{.kind = SourceKind::Disk, .axis = {0, 0, -1}, .radius_mm = 1.0};
    const SourceDesc cylinder{
        .kind = SourceKind::Cylinder, .axis = {1, 0, 0}, .length_mm = 4.0, .radius_mm = 0.5};
    for (const SourceDesc& s : {sphere, cylinder, point, cosine, disk}) {
        EXPECT_LT(mean_turn_deg(s, SamplerKind::Stratified), 3.0);
        EXPECT_GT(mean_turn_deg(s, SamplerKind::Random), 40.0); // independent: 60-90 degrees
    }
}

TEST(Sampling, RayIndicesPastTheRaysEmittedAreRefused) {
    EXPECT_THROW((void)ray_uniforms(SamplerKind::Stratified, 1, 10, 10), std::invalid_argument);
    EXPECT_NO_THROW((void)ray_uniforms(SamplerKind::Stratified, 1, 9, 10));
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
