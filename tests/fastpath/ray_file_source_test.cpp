// A ray file as the source on both tracers (issue 25 items 3 and 7): a file sampled by an
// independent writer from a Lambertian disk (tests/io/write_ray_files.py) gives the mirrored
// cosine law, as FIRD's analytic disk does, within the Monte Carlo noise; the fast path's
// rayset holds the CPU reference's rays, ray for ray; and a file traced in many small
// batches gives the far field of one batch, or fails in a later batch's read with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "farfield/farfield.hpp"
#include "fastpath/fast_tracer.hpp"
#include "io/ray_files_fixture.hpp"
#include "io/scene_file.hpp"
#include "mirror_scene.hpp"
#include "model/ray_file_source.hpp"
#include "model/source.hpp"
#include "reference/reference_tracer.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

// A flat mirror z = -10 mm over a 200 x 200 mm holder, the source at the origin: a ray
// file (its [source] lines given) or, with an empty file name, a Lambertian disk of radius
// 1.5 mm facing down.
Scene mirror_scene(const std::string& file, const std::string& source_lines,
                   const std::string& trace_lines = "") {
    const std::string source =
        file.empty() ? "type = \"disk\"\nradius_mm = 1.5\nnormal = [0.0, 0.0, -1.0]\nflux_lm = "
                       "100.0\n"
                     : fmt::format("type = \"rayfile\"\nfile = \"{}\"\n{}\n", file, source_lines);
    return parse_scene(fmt::format(R"(
[source]
center_mm = [0.0, 0.0, 0.0]
{}
[holder]
min_mm = [-100.0, -100.0, -12.0]
max_mm = [100.0, 100.0, 2.0]
[reflector]
family = "plane"
z0 = -10.0
sx = 0.0
sy = 0.0
cx = 0.0
cy = 0.0
[trace]
seed = 3
max_bounces = 1
farfield = [72, 36]
heightfield = [64, 64]
{}
)",
                                   source, trace_lines),
                       ray_files()("mirror.toml"));
}

// The file's 200 000 rays (a Lambertian disk of radius 1.5 mm, sampled by the writer),
// placed facing down 10 mm over the flat mirror. On the fast path and the CPU reference,
// whole and subsampled to a quarter, each far-field row within 80 degrees of the zenith
// holds the cosine law's share (binomial counts: 4.5 sigma, a false-alarm rate below 1e-4
// over the 16 rows); and the whole file's rows agree with FIRD's analytic disk traced with
// as many rays (two independent binomial counts: 4.5 sqrt(sigma_a^2 + sigma_b^2)).
TEST_F(VulkanTest, ARayFileOfALambertianDiskTracesToTheAnalyticDisksFarField) {
    const Scene file = mirror_scene("disk.tm25ray", "normal = [0.0, 0.0, -1.0]");
    const Scene quarter =
        mirror_scene("disk.tm25ray", "normal = [0.0, 0.0, -1.0]\nsubsample = 0.25");
    const Scene disk = mirror_scene("", "", "rays = 200000");
    ASSERT_EQ(file.trace.rays, 200000u);
    ASSERT_EQ(quarter.trace.rays, 50000u);
    ASSERT_EQ(file.source.flux_lm, 100.0);
    const std::uint32_t w = file.trace.farfield_w, h = file.trace.farfield_h;
    const auto fast = [&](const Scene& s) {
        FastTracer t(ctx(), s, s.trace.seed);
        t.set_reflector(s.reflector);
        const FastRun run = t.run();
        // Every ray's flux accounted for: far field and direct light hold the source's.
        EXPECT_EQ(run.tally.emitted, s.trace.rays);
        EXPECT_EQ(run.tally.farfield + run.tally.direct, s.trace.rays);
        return t.read_farfield();
    };
    const auto reference = [&](const Scene& s) {
        return trace_reference(s.source, Surface::make(s.reflector, s.holder),
                               {.rays = s.trace.rays,
                                .seed = s.trace.seed,
                                .max_bounces = 1,
                                .farfield_w = w,
                                .farfield_h = h})
            .farfield.lm;
    };
    const std::vector<double> disk_rows = far_field_rows_lm(fast(disk), w, h);
    const struct {
        const char* name;
        const Scene& scene;
        std::vector<double> lm;
    } traced[] = {{"ray file, fast path", file, fast(file)},
                  {"ray file, reference", file, reference(file)},
                  {"ray file subsampled, fast path", quarter, fast(quarter)},
                  {"ray file subsampled, reference", quarter, reference(quarter)}};
    for (const auto& t : traced) {
        SCOPED_TRACE(t.name);
        const double rays = double(t.scene.trace.rays);
        const double lm_per_ray = t.scene.source.flux_lm / rays;
        const std::vector<double> rows = far_field_rows_lm(t.lm, w, h);
        for (std::uint32_t row = h / 2; row < h; ++row)
            EXPECT_EQ(rows[row], 0.0) << "a reflection off z = -10 rises; row " << row;
        for (std::uint32_t row = 0; row < h / 2 - 2; ++row) { // gamma < 80 degrees
            const double p = cosine_law_row_fraction(row, h);
            const double sigma_rays = std::sqrt(rays * p * (1 - p));
            EXPECT_NEAR(rows[row] / lm_per_ray, p * rays, 4.5 * sigma_rays) << "row " << row;
            if (t.scene.trace.rays == disk.trace.rays) {
                EXPECT_NEAR(rows[row] / lm_per_ray, disk_rows[row] / lm_per_ray,
                            4.5 * std::sqrt(2.0) * sigma_rays)
                    << "row " << row << " against the analytic disk";
            }
        }
    }
}

// Unequal weights, resampled, tilted, turned and moved: the fast path's rayset is the CPU
// reference's effective rays (read through the same reader and placed in double; the fast
// path's in float), matched to float rounding (1e-5 mm and 1e-5 at these sizes).
TEST_F(VulkanTest, BothTracersEmitTheSameRaysFromARayFile) {
    const Scene s = mirror_scene(
        "weighted.tm25ray", "normal = [0.3, -0.2, -1.0]\nx_axis = [0.0, 1.0, 0.0]", "rays = 30000");
    FastTracer t(ctx(), s, s.trace.seed);
    t.set_reflector(s.reflector);
    (void)t.run();
    std::vector<Ray> gpu = t.rayset();
    std::vector<Ray> cpu;
    emit_ray_file_rays(s.source, s.trace.seed, 0, s.trace.rays, s.trace.rays, [&](const Ray& r) {
        if (ray_meets_box(r, s.holder)) cpu.push_back(r);
    });
    ASSERT_GT(cpu.size(), s.trace.rays / 2);
    // A ray grazing the holder's face may be kept by one precision and not the other.
    ASSERT_NEAR(double(gpu.size()), double(cpu.size()), 2.0);
    const std::size_t matched = rays_matching(gpu, cpu, 1e-5);
    // A resampled ray emitted twice sorts next to itself; near-equal x components may sort
    // apart between float and double.
    EXPECT_GE(double(matched), 0.99 * double(cpu.size()));
}

// Streaming: the file's 200 000 rays in batches of 4999 rays (41 batches, each read from
// the file as it is traced) give the far field of one batch, count for count, and the
// same tally.
TEST_F(VulkanTest, ARayFileTracedInSmallBatchesGivesTheFarFieldOfOneBatch) {
    const Scene s = mirror_scene("disk.tm25ray", "normal = [0.0, 0.0, -1.0]");
    const auto traced = [&](std::uint64_t max_batch_rays) {
        FastTracer t(ctx(), s, s.trace.seed, max_batch_rays);
        t.set_reflector(s.reflector);
        const FastRun run = t.run();
        return std::pair{run.tally, t.read_farfield()};
    };
    const auto [one_tally, one] = traced(0);
    const auto [small_tally, small] = traced(4999);
    EXPECT_EQ(small_tally.farfield, one_tally.farfield);
    EXPECT_EQ(small_tally.direct, one_tally.direct);
    ASSERT_EQ(small.size(), one.size());
    // The same rays fall in each cell; each cell's flux is its count times the flux per ray.
    for (std::size_t c = 0; c < one.size(); ++c)
        ASSERT_EQ(small[c], one[c]) << "cell " << c;
}

// Each batch after the first is read on a host thread while the device traces the one
// before: a file cut after the scene was read fails in such a read (the cut falls in the
// batches past the first), and the trace ends with the reader's one line naming the file
// and the byte, neither a crash nor a hang.
TEST_F(VulkanTest, AFileCutAfterTheSceneWasReadFailsAFastTraceInALaterBatch) {
    const std::string copy = ray_files()("cut_fast.tm25ray");
    std::filesystem::copy_file(ray_files()("disk.tm25ray"), copy,
                               std::filesystem::copy_options::overwrite_existing);
    const Scene s = mirror_scene("cut_fast.tm25ray", "normal = [0.0, 0.0, -1.0]");
    std::filesystem::resize_file(copy, std::filesystem::file_size(copy) / 2);
    FastTracer t(ctx(), s, s.trace.seed, 4999);
    t.set_reflector(s.reflector);
    try {
        (void)t.run();
        FAIL() << "a cut file traced";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(copy + ": byte ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("short file"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace fird::test
