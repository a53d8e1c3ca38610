// fird tolerance (issue 27 item 4): the draws have the stated standard deviations, the
// surface error its RMS and its Gaussian correlation, the beam angle of a cone its angle
// (answers worked out by hand), and a run is reproducible and moves the light as physics
// says a misplaced source does.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "photometry/beam_metrics.hpp"
#include "tolerance/surface_error.hpp"
#include "tolerance/tolerance.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

double sd(const std::vector<double>& v, double mean = 0.0) {
    double s = 0.0;
    for (double x : v)
        s += (x - mean) * (x - mean);
    return std::sqrt(s / double(v.size()));
}

Scene paraboloid() {
    Scene s =
        load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/test/focused_paraboloid_search.toml");
    s.reflector.parameters["fx"] = s.reflector.parameters["fy"] = 3.0; // the source at its focus
    return s;
}

// 20 000 draws: each standard deviation within 3 % (the estimate's own error is
// 1/sqrt(2N) = 0.5 %); a run of one tolerance draws nothing else.
TEST(Tolerance, DrawsHaveTheStatedStandardDeviations) {
    Scene s = paraboloid();
    s.reflector.material.reflectance = 0.8;
    const ToleranceDesc t{
        .source_shift_mm = {0.1, 0.2, 0.3}, .source_tilt_deg = 2.0, .reflectance_sd = 0.02};
    std::vector<double> x, y, z, tx, ty, r;
    for (std::uint64_t k = 0; k < 20000; ++k) {
        const ToleranceDraw d = draw_tolerances(t, s, 7, k);
        x.push_back(d.source_shift_mm.x);
        y.push_back(d.source_shift_mm.y);
        z.push_back(d.source_shift_mm.z);
        tx.push_back(d.tilt_x_deg);
        ty.push_back(d.tilt_y_deg);
        r.push_back(d.reflectance);
    }
    EXPECT_NEAR(sd(x), 0.1, 0.003);
    EXPECT_NEAR(sd(y), 0.2, 0.006);
    EXPECT_NEAR(sd(z), 0.3, 0.009);
    EXPECT_NEAR(sd(tx), 2.0, 0.06);
    EXPECT_NEAR(sd(ty), 2.0, 0.06);
    EXPECT_NEAR(sd(r, 0.8), 0.02, 0.0006);
    const ToleranceDraw only = draw_tolerances(t, s, 7, 3, "source_tilt");
    EXPECT_EQ(only.source_shift_mm, glm::dvec3(0.0));
    EXPECT_EQ(only.reflectance, 0.8);
    EXPECT_EQ(only.tilt_x_deg, draw_tolerances(t, s, 7, 3).tilt_x_deg) << "the joint run's draw";
}

// The field's RMS over 300 realisations at 2 000 points each is the stated RMS (5 %: the
// features' finite count), and its correlation at lag L is exp(-1/2) = 0.607 (the
// Gaussian covariance of the spectral draws; 0.05 absolute).
TEST(Tolerance, SurfaceErrorHasItsRmsAndGaussianCorrelation) {
    const double rms = 0.05, corr = 2.0;
    double z2 = 0.0, zz = 0.0;
    std::size_t n = 0;
    for (std::uint64_t r = 0; r < 300; ++r) {
        const SurfaceError e = draw_surface_error(rms, corr, 3, r);
        for (int i = 0; i < 2000; ++i) {
            const double x = -20.0 + 0.02 * i, y = 0.37 * i - 300.0;
            const double a = e.at(x, y), b = e.at(x + corr, y);
            z2 += a * a;
            zz += a * b;
            ++n;
        }
    }
    EXPECT_NEAR(std::sqrt(z2 / double(n)), rms, 0.05 * rms);
    EXPECT_NEAR(zz / z2, std::exp(-0.5), 0.05);
}

// A smooth lobe I(gamma) = I0 cos^10(gamma) about the zenith, binned cell by cell: its beam
// angle is 2 acos(0.5^(1/10)) = 42.26 degrees (within half a 1-degree row) and its peak I0
// (within 1 %: the polar cap of the first row averages cos^10 over 0 to 1 degree, above
// 0.9984 of I0).
TEST(BeamMetrics, ACosinePowerLobeHasItsAngleAndPeak) {
    const std::uint32_t w = 360, h = 180;
    FarField f{w, h, std::vector<double>(std::size_t(w) * h, 0.0)};
    const double pi = std::numbers::pi, peak_cd = 250.0;
    for (std::uint32_t r = 0; r < h / 2; ++r) {
        const double top = pi / 2 - pi * r / h, bottom = pi / 2 - pi * (r + 1) / h;
        const double sr = 2.0 * pi / w * (std::sin(top) - std::sin(bottom));
        const double gamma = pi * (r + 0.5) / h; // the row's centre, from the zenith
        for (std::uint32_t c = 0; c < w; ++c)
            f.lm[std::size_t(r) * w + c] = peak_cd * std::pow(std::cos(gamma), 10) * sr;
    }
    const BeamMetrics m = beam_metrics(f);
    EXPECT_NEAR(m.beam_angle_deg, 2.0 * std::acos(std::pow(0.5, 0.1)) * 180.0 / pi, 0.5);
    EXPECT_NEAR(m.peak_cd, peak_cd, 0.01 * peak_cd);
}

// The workbench's Stop: a run stopped after the joint realisations has those rows alone,
// says it was stopped, and gives the tolerances' own runs no spread and names no tolerance
// the most sensitive (nothing measured them), where zeros would read as measured.
TEST_F(VulkanTest, AStoppedRunKeepsItsRowsAndRanksNothingItDidNotTrace) {
    Scene s = paraboloid();
    s.trace.rays = 5000;
    std::atomic<bool> stop{false};
    const ToleranceRun run{.tolerances = {.realisations = 3,
                                          .source_shift_mm = glm::dvec3(0.3),
                                          .reflectance_sd = 0.01},
                           .seed = 5,
                           // The nominal luminaire, then the 3 joint realisations: stop there.
                           .progress = [&](const RealisationResult&, std::size_t done,
                                           std::size_t) { stop = done >= 4; },
                           .stop = &stop};
    const ToleranceResult r = run_tolerance(ctx(), s, run);
    EXPECT_TRUE(r.stopped);
    ASSERT_EQ(r.rows.size(), 3u);
    for (const RealisationResult& row : r.rows)
        EXPECT_EQ(row.kind, "joint");
    EXPECT_EQ(r.most_sensitive, "");
    const nlohmann::json j = tolerance_json(r);
    EXPECT_TRUE(j.at("stopped").get<bool>());
    EXPECT_TRUE(j.at("l2").is_object()); // the joint run's spread
    EXPECT_TRUE(j.at("most_sensitive").is_null());
    for (const auto& tolerance : j.at("sensitivities")) {
        EXPECT_TRUE(tolerance.at("l2").is_null()) << tolerance;
        EXPECT_TRUE(tolerance.at("efficiency").is_null()) << tolerance;
    }
}

// A point source at a paraboloid's focus sends a beam to the zenith; shifted by 0.3 mm
// (sd per axis) it blurs and tilts the beam: the realisations' peak intensity is below the
// nominal one at the median, and the shift is the tolerance that moves l2 most (the
// reflectance's 0.01 sd scales the far field by about 1 %). The run is reproducible: the
// same seed gives the same rows.
TEST_F(VulkanTest, AShiftedSourceBlursTheBeamReproducibly) {
    Scene s = paraboloid();
    s.trace.rays = 20000;
    s.reflector.material.reflectance = 0.9;
    const ToleranceRun run{.tolerances = {.realisations = 6,
                                          .source_shift_mm = glm::dvec3(0.3),
                                          .reflectance_sd = 0.01},
                           .seed = 5};
    const ToleranceResult a = run_tolerance(ctx(), s, run);
    ASSERT_EQ(a.rows.size(), 6u * 3u);
    ASSERT_TRUE(a.nominal.l2_lm);
    std::vector<double> peaks;
    for (const RealisationResult& r : a.rows)
        if (r.kind == "joint") peaks.push_back(r.peak_cd);
    EXPECT_LT(spread_of(peaks).median, a.nominal.peak_cd);
    EXPECT_EQ(a.most_sensitive, "source_shift");
    EXPECT_EQ(a.ranked_by, "l2");
    const ToleranceResult b = run_tolerance(ctx(), s, run);
    for (std::size_t k = 0; k < a.rows.size(); ++k) {
        EXPECT_EQ(a.rows[k].l2_lm, b.rows[k].l2_lm) << k;
        EXPECT_EQ(a.rows[k].draw.source_shift_mm, b.rows[k].draw.source_shift_mm) << k;
    }
    const nlohmann::json j = tolerance_json(a);
    for (const char* key : {"realisations", "l2", "efficiency", "peak_cd", "sensitivities"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const char* key : {"median", "p5", "p95"})
        EXPECT_TRUE(j["l2"].contains(key)) << key;
    EXPECT_EQ(j["sensitivities"].size(), 2u);
}

// A surface error traced as a mesh on the fast path: the nominal run traces the same mesh
// grid without the error, so a zero-RMS draw would equal it; an error of 0.05 mm over 2 mm
// blurs the focused beam (lower peak at the median).
TEST_F(VulkanTest, ASurfaceErrorBlursAFocusedBeam) {
    Scene s = paraboloid();
    s.trace.rays = 20000;
    const ToleranceRun run{
        .tolerances = {.realisations = 4, .surface_rms_mm = 0.05, .surface_correlation_mm = 2.0},
        .seed = 2,
        .scratch_dir = ::testing::TempDir()};
    const ToleranceResult r = run_tolerance(ctx(), s, run);
    std::vector<double> peaks;
    for (const RealisationResult& row : r.rows)
        if (row.kind == "joint") {
            peaks.push_back(row.peak_cd);
            EXPECT_NEAR(row.surface_rms_mm, 0.05, 0.03) << "one draw's RMS over the grid";
        }
    EXPECT_LT(spread_of(peaks).median, 0.8 * r.nominal.peak_cd);
}

} // namespace
} // namespace fird::test
