// Every emitter on both tracers (issue 25 items 1, 2, 7), a photometric file's too: the fast path's
// rayset holds the rays the CPU reference emits from the same definition (shaders/emitter.h), and a
// Lambertian disk over a flat mirror gives the mirrored cosine law, an answer worked out
// by hand, on both.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "farfield/farfield.hpp"
#include "fastpath/fast_tracer.hpp"
#include "io/scene_file.hpp"
#include "mirror_scene.hpp"
#include "model/emission_table.hpp"
#include "model/source.hpp"
#include "photometry/photometry_file.hpp"
#include "reference/reference_tracer.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

// The hand-made asymmetric IES file of tests/photometry/data, from a point or a disk.
SourceDesc photometric(const glm::dvec3& normal, double radius_mm) {
    SourceDesc s{.kind = SourceKind::Photometric,
                 .axis = normal,
                 .x_axis = default_x_axis(normal),
                 .radius_mm = radius_mm};
    s.table = emission_table(read_photometry(
        std::string(FIRD_SOURCE_DIR) + "/tests/photometry/data/lm63_2002_asymmetric_emitter.ies"));
    return s;
}

std::vector<SourceDesc> every_emitter() {
    const glm::dvec3 tilted = glm::normalize(glm::dvec3(0.3, -0.2, -1.0));
    return {
        {.kind = SourceKind::Cylinder, .axis = {1, 0.5, 0}, .length_mm = 3, .radius_mm = 0.5},
        {.kind = SourceKind::Sphere, .radius_mm = 1.0},
        {.kind = SourceKind::Point, .emittance = Emittance::Isotropic},
        {.kind = SourceKind::Point, .axis = {0, 0, -1}, .emittance = Emittance::Cosine},
        {.kind = SourceKind::Disk,
         .axis = tilted,
         .x_axis = default_x_axis(tilted),
         .radius_mm = 1.5},
        {.kind = SourceKind::Rectangle,
         .axis = tilted,
         .x_axis = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), tilted)),
         .width_mm = 4.0,
         .height_mm = 1.0},
        photometric(tilted, 0.0),
        photometric(tilted, 1.0),
    };
}

// The rayset is the CPU's effective rays, in float: compare the two lists sorted, a ray
// matching where origin and direction agree to float rounding (1e-5 at these sizes).
TEST_F(VulkanTest, EveryEmitterEmitsTheSameRaysOnBothTracers) {
    for (const SourceDesc& source : every_emitter())
        for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Sobol}) {
            const Scene s = mirror_scene(source, 20000);
            SCOPED_TRACE(fmt::format("{} ({}), {}", int(source.kind), int(source.emittance),
                                     sampler_name(sampler)));
            Scene traced = s;
            traced.trace.sampler = sampler;
            FastTracer t(ctx(), traced, 5);
            t.set_reflector(traced.reflector);
            (void)t.run();
            std::vector<Ray> gpu = t.rayset();
            std::vector<Ray> cpu;
            for (std::uint64_t i = 0; i < s.trace.rays; ++i) {
                const Ray r = emit_ray(s.source, sampler, 5, i, s.trace.rays);
                if (ray_meets_box(r, s.holder)) cpu.push_back(r);
            }
            ASSERT_GT(cpu.size(), s.trace.rays / 4);
            // A ray grazing the holder's face may be kept by one precision and not the other.
            ASSERT_NEAR(double(gpu.size()), double(cpu.size()), 2.0);
            const std::size_t matched = rays_matching(gpu, cpu, 1e-5);
            // Near-equal x components may sort apart between float and double.
            EXPECT_GE(double(matched), 0.99 * double(cpu.size()));
        }
}

// A disk facing straight down, 10 mm over the flat mirror: every ray
// within gamma < atan((100 - 1.5) / 10) = 84 degrees of the axis meets the mirror, so the
// far field's rows above 80 degrees from the zenith hold the cosine law's share of the
// flux, per row, on both tracers. Each row's count is binomial at most (a stratified
// sampler only lowers its variance): 4.5 sigma bounds it for all 16 rows together at a
// false-alarm rate below 1e-4.
TEST_F(VulkanTest, ALambertianDiskOverAFlatMirrorGivesTheMirroredCosineLaw) {
    const SourceDesc disk{.kind = SourceKind::Disk,
                          .axis = {0, 0, -1},
                          .x_axis = {1, 0, 0},
                          .radius_mm = 1.5,
                          .flux_lm = 100.0};
    const std::uint64_t rays = 400000;
    const Scene s = mirror_scene(disk, rays);
    FastTracer t(ctx(), s, s.trace.seed);
    t.set_reflector(s.reflector);
    const FastRun fast = t.run();
    const std::vector<double> fast_lm = t.read_farfield();
    const ReferenceResult ref = trace_reference(s.source, Surface::make(s.reflector, s.holder),
                                                {.rays = rays,
                                                 .seed = s.trace.seed,
                                                 .max_bounces = 1,
                                                 .farfield_w = s.trace.farfield_w,
                                                 .farfield_h = s.trace.farfield_h});
    EXPECT_EQ(fast.tally.discarded, 0u) << "a downward emitter inside the box meets it";
    const std::uint32_t w = s.trace.farfield_w, h = s.trace.farfield_h;
    const double lm_per_ray = disk.flux_lm / double(rays);
    for (const auto& [name, lm] :
         {std::pair{"fast path", fast_lm}, std::pair{"reference", ref.farfield.lm}}) {
        SCOPED_TRACE(name);
        const std::vector<double> rows = far_field_rows_lm(lm, w, h);
        double below_horizon = 0.0;
        for (std::uint32_t row = h / 2; row < h; ++row)
            below_horizon += rows[row];
        EXPECT_EQ(below_horizon, 0.0) << "a reflection off z = -10 rises";
        for (std::uint32_t row = 0; row < h / 2 - 2; ++row) { // gamma < 80 degrees
            const double p = cosine_law_row_fraction(row, h);
            const double expected_rays = p * double(rays);
            const double sigma_rays = std::sqrt(double(rays) * p * (1 - p));
            EXPECT_NEAR(rows[row] / lm_per_ray, expected_rays, 4.5 * sigma_rays) << "row " << row;
        }
    }
}

// A bare Lambertian cylinder standing along z, its direct light binned: its intensity goes as
// the sine of the angle theta to its axis (its projected area), I = (flux / pi^2) sin theta,
// so far-field row [theta_top, theta_bottom] (rows are bands of theta here) holds the
// fraction F(theta_bottom) - F(theta_top) of the flux, F(theta) = (theta - sin theta cos
// theta) / pi, worked out by hand. The holder (6 x 6 mm, 500 mm below) takes the rays within
// 0.4 degrees of the nadir, a share of 7e-8. Each row's count is binomial at most: 4.5 sigma
// over the 36 rows, on both tracers, with both samplers (the stratified sampler draws the
// cylinder's direction from its stratified uniforms, emitter.h).
TEST_F(VulkanTest, ABareCylinderEmitsTheSineLawOfItsProjectedAreaOnBothTracers) {
    const SourceDesc cylinder{.kind = SourceKind::Cylinder,
                              .axis = {0, 0, 1},
                              .length_mm = 4.1,
                              .radius_mm = 0.65,
                              .flux_lm = 100.0};
    const std::uint64_t rays = 400000;
    const auto band = [](double theta) {
        return (theta - std::sin(theta) * std::cos(theta)) / std::numbers::pi;
    };
    for (SamplerKind sampler : {SamplerKind::Stratified, SamplerKind::Random}) {
        SCOPED_TRACE(sampler_name(sampler));
        Scene s = mirror_scene(cylinder, rays);
        s.holder = {{-3.0, -3.0, -501.0}, {3.0, 3.0, -500.0}};
        s.reflector.parameters["z0"] = -500.5;
        s.trace.direct = DirectLight::Include;
        s.trace.sampler = sampler;
        FastTracer t(ctx(), s, s.trace.seed);
        t.set_reflector(s.reflector);
        const FastRun fast = t.run();
        EXPECT_EQ(fast.tally.direct, rays);
        const auto ref = trace_reference(s.source, Surface::make(s.reflector, s.holder),
                                         {.rays = rays,
                                          .seed = s.trace.seed,
                                          .sampler = sampler,
                                          .max_bounces = 1,
                                          .farfield_w = s.trace.farfield_w,
                                          .farfield_h = s.trace.farfield_h,
                                          .direct = DirectLight::Include});
        EXPECT_EQ(ref.tally.direct, rays);
        const std::uint32_t w = s.trace.farfield_w, h = s.trace.farfield_h;
        const double lm_per_ray = cylinder.flux_lm / double(rays);
        for (const auto& [name, lm] :
             {std::pair{"fast path", t.read_farfield()}, std::pair{"reference", ref.farfield.lm}}) {
            SCOPED_TRACE(name);
            const std::vector<double> rows = far_field_rows_lm(lm, w, h);
            for (std::uint32_t row = 0; row < h; ++row) {
                const double p =
                    band(std::numbers::pi * (row + 1) / h) - band(std::numbers::pi * row / h);
                const double sigma_rays = std::sqrt(double(rays) * p * (1 - p));
                EXPECT_NEAR(rows[row] / lm_per_ray, p * double(rays), 4.5 * sigma_rays + 1.0)
                    << "row " << row;
            }
        }
    }
}

} // namespace
} // namespace fird::test
