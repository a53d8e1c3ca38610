// The views against golden images (lavapipe; stated tolerances, a diff image written on
// failure), and geometry that does not depend on pixels: the picked ray's recorded walk
// and its path against the CPU reference.
//
// Regenerate the goldens (after a deliberate change to a view) with
//     scripts/update_goldens.sh
// which runs these tests with FIRD_UPDATE_GOLDENS=1: they then write the goldens.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include <glm/geometric.hpp>

#include "evaluation/evaluation.hpp"
#include "golden_image.hpp"
#include "io/scene_file.hpp"
#include "plot/canvas.hpp"
#include "plot/colormap.hpp"
#include "reference/reference_tracer.hpp"
#include "reference/surface_hit.hpp"
#include "traced_scene.hpp"
#include "views.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

namespace fs = std::filesystem;

constexpr int kW = 320, kH = 200;

Scene paraboloid() {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/test/focused_paraboloid.toml");
}

void expect_like_view_golden(const std::vector<std::uint8_t>& rgba, int w, int h, const char* name,
                             test::Drawn drawn) {
    test::expect_like_golden(
        rgba, w, h, (fs::path(FIRD_SOURCE_DIR) / "tests/render/golden" / name).string(), drawn);
}

class Views : public VulkanTest {
  protected:
    static void SetUpTestSuite() {
        VulkanTest::SetUpTestSuite();
        // Pick the first sample ray that meets the reflector (some leave directly).
        Scene s = paraboloid();
        s.trace.rays = 20000;
        const auto indices = sample_effective_ray_indices(s, 60);
        const Surface surface = Surface::make(s.reflector, s.holder);
        std::size_t k = 0;
        while (k < indices.size() &&
               !first_surface_hit(
                    surface,
                    emit_ray(s.source, s.trace.sampler, s.trace.seed, indices[k], s.trace.rays),
                    0.0)
                    .t)
            ++k;
        pick_ = indices.at(k);
        traced_ = std::make_unique<render::TracedScene>(
            render::trace_for_views(ctx(), s, {.paths = 60, .pick = pick_}));
    }
    static void TearDownTestSuite() {
        traced_.reset();
        VulkanTest::TearDownTestSuite();
    }
    static std::unique_ptr<render::TracedScene> traced_;
    static std::uint64_t pick_; // a rayset index
};
std::unique_ptr<render::TracedScene> Views::traced_;
std::uint64_t Views::pick_ = 0;

// Pixels of a viewport picture in the magenta (0.95, 0.15, 0.55) of the press's mark: red
// high, green low, blue between; within the cross's half width (a fiftieth of the
// holder's diagonal, a few pixels here) of the point `at` as the camera projects it.
int magenta_near(const std::vector<std::uint8_t>& img, const render::OrbitCamera& camera,
                 glm::dvec3 at) {
    const glm::vec4 clip =
        render::view_projection(camera, double(kW) / kH) * glm::vec4(glm::vec3(at), 1.0f);
    const double px = (clip.x / clip.w * 0.5 + 0.5) * kW, py = (clip.y / clip.w * 0.5 + 0.5) * kH;
    int count = 0;
    for (int y = std::max(0, int(py) - 8); y < std::min(kH, int(py) + 9); ++y)
        for (int x = std::max(0, int(px) - 8); x < std::min(kW, int(px) + 9); ++x) {
            const std::uint8_t* p = &img[(std::size_t(y) * kW + std::size_t(x)) * 4];
            count += p[0] > 200 && p[1] < 90 && p[2] > 90 && p[2] < 180;
        }
    return count;
}

TEST_F(Views, ViewportMatchesItsGolden) {
    render::ViewportRenderer renderer(ctx());
    render::ViewportOptions o{.camera = render::frame_holder(traced_->scene.holder),
                              .quadtree = true,
                              .quadtree_level = 5,
                              .height_colours = true};
    const auto rgba = render::render_viewport(ctx(), renderer, traced_->viewport, o, kW, kH);
    expect_like_view_golden(rgba, kW, kH, "viewport.png", test::Drawn::OnDevice);
}

// Coloured by slope: the paraboloid's steepest point (the press measures') is marked by a
// magenta cross drawn where the camera projects it, and nowhere without slope colours;
// the picture matches its golden.
TEST_F(Views, ViewportColoursBySlopeAndMarksTheSteepestPoint) {
    ASSERT_TRUE(traced_->viewport.steepest_mm);
    render::ViewportRenderer renderer(ctx());
    render::ViewportOptions o{.camera = render::frame_holder(traced_->scene.holder),
                              .rays = false,
                              .slope_colours = true};
    const auto rgba = render::render_viewport(ctx(), renderer, traced_->viewport, o, kW, kH);
    const glm::dvec3 at = *traced_->viewport.steepest_mm;
    EXPECT_GT(magenta_near(rgba, o.camera, at), 3);
    o.slope_colours = false;
    EXPECT_EQ(magenta_near(render::render_viewport(ctx(), renderer, traced_->viewport, o, kW, kH),
                           o.camera, at),
              0);
    expect_like_view_golden(rgba, kW, kH, "viewport_slope.png", test::Drawn::OnDevice);
}

// Coloured by curvature: seen from above, the paraboloid z = z0 + r^2 / (4 f) (f = 3 mm)
// has, at radius r, principal curvatures (1 / 2f) / (1 + r^2 / 4f^2)^(3/2) (along the
// meridian) and (1 / 2f) / (1 + r^2 / 4f^2)^(1/2) (around it, the larger): 1/6 per mm at
// the apex, 0.1179 at r = 6 mm; beyond the clamp (r = 10.95 mm) the holder's plane has
// none. Each pixel there must have the colour of that curvature on the log scale from
// kCurvatureFlatRadiusMm to kCurvatureTightRadiusMm (the map restated here from
// surface.frag), lit as the shader lights a surface of that normal. The fragment's
// Hessian is the gradient's difference across a triangle: exact for this quadratic. Bound:
// a pixel's centre lies within half a pixel (0.07 mm) of the point, where the normal
// turns by < 1 degree and the curvature by < 0.1 % (< 2 levels of 255 together), plus
// 8-bit rounding: 3 levels. The tightest bend is the apex (radius 2f = 6 mm; the press
// measures leave the clamped plane and its rim out), marked by a magenta cross there,
// whose arms (a fiftieth of the holder's diagonal, 1.15 mm) the probes keep clear of.
TEST_F(Views, ViewportColoursByCurvatureAndMarksTheTightestBend) {
    const render::ViewportContent& c = traced_->viewport;
    ASSERT_TRUE(c.tightest_mm);
    // Central differences of the analytic gradient: exact for a quadratic but for rounding.
    EXPECT_NEAR(c.min_radius_mm, 6.0, 1e-6);
    EXPECT_NEAR(std::hypot(c.tightest_mm->x, c.tightest_mm->y), 0.0, 0.1); // one grid step
    render::ViewportRenderer renderer(ctx());
    render::ViewportOptions o{.camera = render::frame_holder(traced_->scene.holder),
                              .rays = false,
                              .curvature_colours = true};
    o.camera.elevation_deg = 89.0;
    const auto rgba = render::render_viewport(ctx(), renderer, c, o, kW, kH);
    const glm::mat4 vp = render::view_projection(o.camera, double(kW) / kH);
    const auto pixel_at = [&](glm::dvec3 at) {
        const glm::vec4 clip = vp * glm::vec4(glm::vec3(at), 1.0f);
        const int x = int(std::floor((clip.x / clip.w * 0.5 + 0.5) * kW));
        const int y = int(std::floor((clip.y / clip.w * 0.5 + 0.5) * kH));
        return &rgba[(std::size_t(y) * kW + std::size_t(x)) * 4];
    };
    const auto map = [](double t) { // surface.frag's height_colour
        const auto mix = [](glm::dvec3 a, glm::dvec3 b, double u) { return a + (b - a) * u; };
        return mix(mix({0.16, 0.20, 0.45}, {0.10, 0.62, 0.60}, std::clamp(2.0 * t, 0.0, 1.0)),
                   {0.98, 0.86, 0.30}, std::clamp(2.0 * t - 1.0, 0.0, 1.0));
    };
    const auto expected = [&](double curvature_per_mm, glm::dvec3 normal) {
        const double lo = -std::log10(render::kCurvatureFlatRadiusMm),
                     hi = -std::log10(render::kCurvatureTightRadiusMm);
        const double t = curvature_per_mm > 0.0
                             ? std::clamp((std::log10(curvature_per_mm) - lo) / (hi - lo), 0.0, 1.0)
                             : 0.0;
        const glm::dvec3 n = glm::normalize(normal);
        const double light =
            0.25 + 0.6 * std::abs(glm::dot(n, glm::normalize(glm::dvec3(-0.45, -0.55, 0.70)))) +
            0.2 * std::abs(glm::dot(n, glm::normalize(glm::dvec3(0.6, 0.3, 0.4))));
        return map(t) * light * 255.0;
    };
    const double f = 3.0, z0 = -10.0;
    struct Probe {
        glm::dvec3 at;
        double curvature;
        glm::dvec3 normal;
    };
    // On the paraboloid at (x, y): its height, normal and larger principal curvature.
    const auto on_paraboloid = [&](double x, double y) {
        const double r2 = x * x + y * y;
        return Probe{{x, y, z0 + r2 / (4 * f)},
                     1.0 / (2 * f) / std::sqrt(1.0 + r2 / (4 * f * f)),
                     {-x / (2 * f), -y / (2 * f), 1.0}};
    };
    const Probe probes[] = {on_paraboloid(1.5, 1.5),
                            on_paraboloid(6.0, 0.0),
                            on_paraboloid(-4.0, 5.0),
                            {{15.0, 15.0, 0.0}, 0.0, {0.0, 0.0, 1.0}}};
    for (const Probe& p : probes) {
        SCOPED_TRACE(testing::Message() << "at " << p.at.x << ", " << p.at.y);
        const std::uint8_t* px = pixel_at(p.at);
        const glm::dvec3 want = expected(p.curvature, p.normal);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(double(px[k]), want[k], 3.0) << "channel " << k;
    }
    // The mark's arms reach out from under the point source drawn above the apex.
    EXPECT_GT(magenta_near(rgba, o.camera, *c.tightest_mm), 3);
    expect_like_view_golden(rgba, kW, kH, "viewport_curvature.png", test::Drawn::OnDevice);
}

// The pictures of a far field traced by the CPU reference: the drawing is what is tested,
// and its input is then the same on every device (on NVIDIA's driver, 2026-12-04, the fast
// path's far field at these 20000 rays moved a few rays into neighbouring cells, as float
// precision lets it, which at a few rays a cell shows in the picture).
TEST_F(Views, FarFieldAndPlotsMatchTheirGoldens) {
    const Scene& s = traced_->scene;
    ASSERT_FALSE(traced_->farfield.desired); // no target: the obtained far field alone
    render::FarFieldContent farfield = traced_->farfield;
    farfield.obtained =
        trace_reference(s.source, Surface::make(s.reflector, s.holder), reference_options(s))
            .farfield;
    plot::Canvas far{640, 400};
    render::draw_farfield_view(far, {0, 0, 640, 400}, farfield, {});
    expect_like_view_golden(far.rgba(), 640, 400, "farfield.png", test::Drawn::OnHost);
    plot::Canvas plots{kW * 2, kH * 2};
    render::draw_profile_plots(plots, {0, 0, kW * 2.0, kH * 2.0}, farfield);
    expect_like_view_golden(plots.rgba(), kW * 2, kH * 2, "plots.png", test::Drawn::OnHost);
}

// The recorded walk of the picked ray: every node it tests contains the ray's position
// (in texels), in order along the ray, and the last one of its first bounce is the
// texel where the reference tracer's exact surface is hit.
TEST_F(Views, PickedRaysWalkVisitsNodesAlongItsPathAndEndsAtTheReferenceHit) {
    const Scene& s = traced_->scene;
    ASSERT_TRUE(traced_->viewport.picked);
    const Ray ray = emit_ray(s.source, s.trace.sampler, s.trace.seed, pick_, s.trace.rays);
    const auto& walk = traced_->viewport.picked->walk;
    ASSERT_FALSE(walk.empty());
    const double tx = (s.holder.max_mm.x - s.holder.min_mm.x) / s.trace.heightfield_w;
    const double ty = (s.holder.max_mm.y - s.holder.min_mm.y) / s.trace.heightfield_h;
    double t_prev = -1.0;
    const WalkStep* last = nullptr;
    for (const WalkStep& w : walk) {
        if (w.bounce != 0) continue;
        const glm::dvec3 p = ray.origin + double(w.t) * ray.direction;
        const double u = (p.x - s.holder.min_mm.x) / tx, v = (p.y - s.holder.min_mm.y) / ty;
        const double span = double(1u << w.level);
        EXPECT_GE(u, w.x * span - 1e-2) << w.level;
        EXPECT_LE(u, (w.x + 1) * span + 1e-2) << w.level;
        EXPECT_GE(v, w.y * span - 1e-2) << w.level;
        EXPECT_LE(v, (w.y + 1) * span + 1e-2) << w.level;
        EXPECT_GE(w.t, t_prev - 1e-4);
        t_prev = w.t;
        last = &w;
    }
    ASSERT_TRUE(last);
    EXPECT_EQ(last->level, 0u);
    const SurfaceHit hit = first_surface_hit(Surface::make(s.reflector, s.holder), ray, 0.0);
    ASSERT_TRUE(hit.t);
    const glm::dvec3 h = ray.origin + *hit.t * ray.direction;
    EXPECT_NEAR(double(last->x), std::floor((h.x - s.holder.min_mm.x) / tx), 1.0);
    EXPECT_NEAR(double(last->y), std::floor((h.y - s.holder.min_mm.y) / ty), 1.0);
    // The recorded path's vertices against the reference, within the hit tolerance.
    std::vector<glm::dvec3> ref;
    (void)trace_path(Surface::make(s.reflector, s.holder), s.holder, ray, s.trace.max_bounces,
                     s.trace.bounce_policy, &ref);
    const RayPath& path = traced_->viewport.picked->path;
    ASSERT_GE(path.vertices.size(), 2u);
    EXPECT_LT(glm::length(path.vertices[1] - ref[1]), 0.05 * tx);
}

// The far-field readout (farfield_cell_at) names the cell the picture shows under the
// mouse, over the whole of every map: a far field lit in one cell, in a known direction
// (farfield_cell, the tally's own binning), drawn with a desired far field lit elsewhere;
// the pixels drawn in that cell's colour are found by scanning each map of the kind
// checked, and the readout at each must be that cell in that map. Checked for every
// selection the panel offers (all maps in one column or three, or one alone), at a panel's
// small size (the compact picture), a narrow and a wide (polar curves beside) size, with the
// whole sphere and a zoomed band shown.
using TracedConstraints = VulkanTest;

// A reflector that breaks a press's constraint is still traced for the views (only a
// search refuses it), and carries each constraint met or broken for the scene panel: the
// mirror's slope is atan(hypot(sx, sy)) everywhere, its depth its rise across the holder.
TEST_F(TracedConstraints, ATracedReflectorCarriesItsConstraintsMetOrBroken) {
    Scene s = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml");
    s.reflector.constraints.max_slope_deg = 8.0;
    s.reflector.constraints.max_depth_mm = 100.0;
    const render::TracedScene t = render::trace_for_views(
        ctx(), s, {.parameters = {{"sx", 0.15}, {"sy", -0.1}}, .rays = 2000, .paths = 0});
    ASSERT_EQ(t.constraints.size(), 2u);
    EXPECT_EQ(t.constraints[0].name, "max_slope_deg");
    EXPECT_NEAR(t.constraints[0].value, std::atan(std::hypot(0.15, 0.1)) * 180.0 / std::numbers::pi,
                1e-9);
    EXPECT_FALSE(t.constraints[0].met);
    EXPECT_EQ(t.constraints[1].name, "max_depth_mm");
    EXPECT_TRUE(t.constraints[1].met);
    s.reflector.constraints = {};
    EXPECT_TRUE(render::trace_for_views(ctx(), s, {.rays = 2000, .paths = 0}).constraints.empty());
}

TEST(FarFieldReadout, TheCellUnderAPixelIsTheCellDrawnThere) {
    const std::uint32_t W = 36, H = 18;
    const auto direction = [](double az_deg, double alt_deg) {
        const double az = az_deg * M_PI / 180.0, alt = alt_deg * M_PI / 180.0;
        return glm::dvec3{std::cos(alt) * std::cos(az), std::cos(alt) * std::sin(az),
                          std::sin(alt)};
    };
    // The cell at half the peak (a colour of its own: the peak's is the background's
    // white); the peak in another cell of the same band, the same in both far fields (so
    // the difference's peak is the cell's +0.5 and the desired's -0.5 elsewhere).
    // (An azimuth window shown must hold both: colours scale to the peak in view.)
    const auto lit = [&](const glm::dvec3& d) {
        FarField f{W, H, std::vector<double>(std::size_t(W) * H, 0.0)};
        f.lm[farfield_cell(glm::normalize(d), W, H)] = 0.5;
        f.lm[farfield_cell(direction(110.0, 30.0), W, H)] = 1.0;
        return f;
    };
    // Azimuth -110 deg, altitude 30 deg (the "-110 reads -30.7"): far left.
    const glm::dvec3 d = direction(-110.0, 30.0);
    const std::uint32_t cell = farfield_cell(glm::normalize(d), W, H);
    render::FarFieldContent c{.obtained = lit(d), .desired = lit(direction(20.0, 45.0))};
    using K = render::FarFieldMapKind;
    // The cell's colour in each map: half the peak in the obtained, the positive end of
    // the diverging scale in the difference.
    const auto cell_colour = [](K kind) {
        return kind == K::Obtained ? plot::sequential_colour(0.5) : plot::diverging_colour(1.0);
    };
    struct Selection {
        std::optional<K> only;
        int columns;
        K checked;
        std::size_t maps;
    };
    const Selection selections[] = {{{}, 1, K::Obtained, 3},
                                    {{}, 3, K::Obtained, 3},
                                    {K::Obtained, 1, K::Obtained, 1},
                                    {K::Difference, 1, K::Difference, 1}};
    for (const auto& [w, h] : {std::pair{340, 240}, std::pair{640, 900}, std::pair{1200, 900}})
        for (const Selection& sel : selections)
            for (const auto& [band, across] :
                 {std::pair<std::optional<std::pair<double, double>>,
                            std::optional<std::pair<double, double>>>{},
                  {std::pair{60.0, 0.0}, std::nullopt},
                  {std::pair{60.0, 0.0}, std::pair{-160.0, 140.0}}}) {
                // Three maps in three columns at 340 px are each too narrow to hold a cell.
                if (w < 600 && sel.columns > 1) continue;
                SCOPED_TRACE(testing::Message()
                             << w << " x " << h << ", " << sel.maps << " maps in " << sel.columns
                             << " columns" << (band ? ", zoomed" : "")
                             << (across ? " across" : ""));
                plot::Canvas cv{w, h};
                const render::FarFieldViewOptions o{.altitude_deg = band,
                                                    .azimuth_deg = across,
                                                    .only = sel.only,
                                                    .columns = sel.columns};
                render::draw_farfield_view(cv, {0, 0, double(w), double(h)}, c, o);
                const auto maps = render::farfield_view_maps({0, 0, double(w), double(h)}, c, o);
                ASSERT_EQ(maps.size(), sel.maps);
                const auto rgba = cv.rgba();
                const plot::Rgb want = cell_colour(sel.checked);
                std::size_t found = 0;
                for (const render::FarFieldViewMap& m : maps) {
                    if (m.kind != sel.checked) continue;
                    const plot::Rect& r = m.placement.map;
                    // Every pixel of the map drawn in the cell's colour reads that cell.
                    for (int y = int(r.y); y < int(r.y + r.h); ++y)
                        for (int x = int(r.x); x < int(r.x + r.w); ++x) {
                            const std::size_t i = (std::size_t(y) * w + x) * 4;
                            if (rgba[i] != want[0] || rgba[i + 1] != want[1] ||
                                rgba[i + 2] != want[2])
                                continue;
                            ++found;
                            const auto at =
                                render::farfield_cell_at(maps, c.obtained, x + 0.5, y + 0.5);
                            ASSERT_TRUE(at) << x << ", " << y;
                            EXPECT_EQ(at->kind, sel.checked);
                            EXPECT_EQ(std::size_t(at->row) * W + at->column, cell)
                                << x << ", " << y;
                        }
                }
                // A cell of 10 deg spans several pixels at these sizes.
                EXPECT_GT(found, 8u);
            }
}

} // namespace
} // namespace fird::test
