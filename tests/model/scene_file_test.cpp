// Scene files: the paper's scenes load and round-trip; every malformed scene gets an
// error naming the file, the key and the line.
#include <filesystem>
#include <fstream>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "io/scene_file.hpp"

namespace fird {
namespace {

const std::string kScenes = std::string(FIRD_SOURCE_DIR) + "/scenes/";

class SceneRoundTrip : public ::testing::TestWithParam<std::string> {};

TEST_P(SceneRoundTrip, WrittenBackParsesToTheSameScene) {
    const Scene a = load_scene(kScenes + GetParam());
    const std::string text = scene_to_toml(a);
    const Scene b = parse_scene(text, kScenes + GetParam());
    EXPECT_EQ(a, b) << text;
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneRoundTrip,
                         ::testing::Values("model_a.toml", "model_b.toml", "model_c.toml",
                                           "test/flat_mirror.toml", "test/focused_paraboloid.toml",
                                           "test/bspline_dish.toml", "test/mesh_dish.toml",
                                           "test/freeform_search.toml", "test/profile_dish.toml"));

TEST(SceneFile, PaperScenesHaveThePaperValues) {
    const Scene a = load_scene(kScenes + "model_a.toml");
    EXPECT_EQ(a.source.kind, SourceKind::Cylinder);
    EXPECT_DOUBLE_EQ(a.source.length_mm, 4.1);
    EXPECT_DOUBLE_EQ(a.source.radius_mm, 0.65);
    EXPECT_EQ(a.trace.rays, 10000000u);
    EXPECT_EQ(a.trace.heightfield_w, 1200u);
    EXPECT_EQ(a.target.parameters.at("fx"), 15.0);
    const Scene b = load_scene(kScenes + "model_b.toml");
    EXPECT_EQ(b.trace.max_bounces, 5u);
    EXPECT_EQ(b.trace.rays, 5000000u);
    const Scene c = load_scene(kScenes + "model_c.toml");
    EXPECT_EQ(c.trace.max_bounces, 6u);
    EXPECT_EQ(c.target.parameters.at("w"), 0.5);
}

// A flat mirror's holder, reflector and trace: the rest of a scene whose [source] a test writes.
const std::string kAfterSource = R"(
[holder]
min_mm = [-10.0, -10.0, -12.0]
max_mm = [10.0, 10.0, 0.0]
[reflector]
family = "plane"
z0 = -10.0
sx = 0.0
sy = 0.0
cx = 0.0
cy = 0.0
[trace]
rays = 1000
max_bounces = 1
)";

// A point source's table: the head of a scene whose rest is kAfterSource.
const std::string kPointSource = R"([source]
type = "point"
center_mm = [0.0, 0.0, -2.0]
flux_lm = 100.0
)";

// A reflector's finish and the direct light read as written and round-trip; their
// defaults are the paper's perfect mirror without direct light.
TEST(SceneFile, AMaterialAndDirectLightReadAndRoundTrip) {
    const Scene plain = parse_scene(kPointSource + kAfterSource, "plain.toml");
    EXPECT_EQ(plain.reflector.material.reflectance, 1.0);
    EXPECT_EQ(plain.reflector.material.spread_deg, 0.0);
    EXPECT_EQ(plain.trace.direct, DirectLight::Exclude);
    const Scene s = parse_scene(kPointSource + kAfterSource + R"(direct = "include"
[reflector.material]
reflectance = 0.88
spread_deg = 1.5
lobe = "phong"
)",
                                "finished.toml");
    EXPECT_EQ(s.reflector.material.reflectance, 0.88);
    EXPECT_EQ(s.reflector.material.spread_deg, 1.5);
    EXPECT_EQ(s.reflector.material.lobe, SpreadLobe::Phong);
    EXPECT_EQ(s.trace.direct, DirectLight::Include);
    EXPECT_EQ(parse_scene(scene_to_toml(s), "finished.toml"), s);
    EXPECT_EQ(parse_scene(scene_to_toml(plain), "plain.toml"), plain);
}

// The press's constraints read as written, each optional (absent: no limit), and
// round-trip; a scene without them writes none.
TEST(SceneFile, ThePresssConstraintsReadAndRoundTrip) {
    const Scene plain = parse_scene(kPointSource + kAfterSource, "plain.toml");
    EXPECT_FALSE(plain.reflector.constraints.any());
    EXPECT_EQ(scene_to_toml(plain).find("constraints"), std::string::npos);
    const Scene s = parse_scene(kPointSource + kAfterSource + R"([reflector.constraints]
max_slope_deg = 55.0
max_depth_mm = 12
)",
                                "pressed.toml");
    EXPECT_EQ(s.reflector.constraints.max_slope_deg, 55.0);
    EXPECT_FALSE(s.reflector.constraints.min_radius_mm);
    EXPECT_EQ(s.reflector.constraints.max_depth_mm, 12.0);
    EXPECT_EQ(parse_scene(scene_to_toml(s), "pressed.toml"), s);
    Scene all = s;
    all.reflector.constraints.min_radius_mm = 2.5;
    EXPECT_EQ(parse_scene(scene_to_toml(all), "all.toml"), all);
}

// [source.optimize] reads the centre's and the tilts' ranges and round-trips.
TEST(SceneFile, SourceOptimizeReadsItsRangesAndRoundTrips) {
    const Scene s = parse_scene(R"([source]
type = "disk"
center_mm = [0.0, 0.0, -2.0]
normal = [0.0, 0.0, -1.0]
radius_mm = 0.5
flux_lm = 100.0
[source.optimize]
z_mm = { min = -4.0, max = -1.0, step = 0.5 }
tilt_x_deg = { min = -10.0, max = 10.0, step = 2.5 }
)" + kAfterSource,
                                "moving.toml");
    ASSERT_EQ(s.source_optimize.size(), 2u);
    EXPECT_EQ(s.source_optimize.at("z_mm"), (ParameterRange{-4.0, -1.0, 0.5}));
    EXPECT_EQ(s.source_optimize.at("tilt_x_deg"), (ParameterRange{-10.0, 10.0, 2.5}));
    EXPECT_EQ(parse_scene(scene_to_toml(s), "moving.toml"), s);
}

// A disk and a rectangle, tilted and turned, read as written and round-trip; a normal and
// an x_axis not of unit length are made unit, the x_axis perpendicular to the normal.
TEST(SceneFile, DiskAndRectangleSourcesReadTheirFrameAndRoundTrip) {
    const std::string head = R"([source]
center_mm = [0.0, 0.0, -2.0]
flux_lm = 100.0
)";
    const Scene disk = parse_scene(
        head + "type = \"disk\"\nradius_mm = 1.5\nnormal = [0.0, 0.0, -2.0]\n" + kAfterSource,
        "disk.toml");
    EXPECT_EQ(disk.source.kind, SourceKind::Disk);
    EXPECT_EQ(disk.source.axis, glm::dvec3(0, 0, -1));
    EXPECT_EQ(disk.source.x_axis, glm::dvec3(1, 0, 0)) << "the default";
    EXPECT_EQ(disk.source.radius_mm, 1.5);
    const Scene rect = parse_scene(head +
                                       "type = \"rectangle\"\nsize_mm = [4.0, 1.0]\n"
                                       "normal = [0.0, 1.0, -1.0]\nx_axis = [3.0, 1.0, 0.0]\n" +
                                       kAfterSource,
                                   "rect.toml");
    EXPECT_EQ(rect.source.kind, SourceKind::Rectangle);
    EXPECT_NEAR(glm::length(rect.source.axis - glm::dvec3(0, 1, -1) / std::sqrt(2.0)), 0, 1e-15);
    EXPECT_NEAR(glm::dot(rect.source.x_axis, rect.source.axis), 0.0, 1e-15);
    EXPECT_NEAR(glm::length(rect.source.x_axis), 1.0, 1e-15);
    EXPECT_GT(rect.source.x_axis.x, 0.9) << "+x, the given side, made perpendicular";
    EXPECT_EQ(rect.source.width_mm, 4.0);
    EXPECT_EQ(rect.source.height_mm, 1.0);
    for (const Scene& s : {disk, rect})
        EXPECT_EQ(parse_scene(scene_to_toml(s), "again.toml"), s) << scene_to_toml(s);
}

// A photometric source reads its file beside the scene, takes the file's flux unless
// flux_lm rescales it, and round-trips; a file that is not there is refused naming `file`.
TEST(SceneFile, APhotometricSourceReadsItsFileBesideTheScene) {
    const std::string path = kScenes + "test/photometric.toml"; // not read: names the folder
    const std::string head = R"([source]
type = "photometric"
center_mm = [0.0, 0.0, -2.0]
file = "../../tests/photometry/data/lm63_2002_asymmetric_emitter.ies"
)";
    const Scene own = parse_scene(head + kAfterSource, path);
    EXPECT_EQ(own.source.kind, SourceKind::Photometric);
    EXPECT_EQ(own.source.radius_mm, 0.0) << "a point by default";
    ASSERT_TRUE(own.source.table.floats);
    // The file: I = 100 (1 + 0.3 cos C + 0.3 sin C) cos(gamma) over the lower hemisphere.
    // Its flux is 100 pi lm: the cosine lobe's; the C terms, interpolated linearly between
    // 45-degree planes, sum to 0 over the turn; and the interpolation, linear in
    // cos(gamma), is exact for cos(gamma) itself. 1e-3 lm bounds the file's rounding to
    // 4 decimals (5e-5 cd over 2 pi sr).
    EXPECT_NEAR(own.source.flux_lm, 100.0 * std::numbers::pi, 1e-3);
    EXPECT_EQ(parse_scene(scene_to_toml(own), path), own) << scene_to_toml(own);
    const Scene scaled =
        parse_scene(head + "flux_lm = 500.0\nradius_mm = 1.0\n" + kAfterSource, path);
    EXPECT_EQ(scaled.source.flux_lm, 500.0);
    EXPECT_EQ(scaled.source.radius_mm, 1.0);
    EXPECT_EQ(parse_scene(scene_to_toml(scaled), path), scaled);
    try {
        (void)parse_scene(R"([source]
type = "photometric"
center_mm = [0.0, 0.0, -2.0]
file = "nowhere.ies"
)" + kAfterSource,
                          path);
        FAIL() << "a missing file was accepted";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("[source] file:"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// A valid base scene; each bad case replaces one line of it.
const std::string kBase = R"([source]
type = "sphere"
center_mm = [5.0, 5.0, -2.0]
radius_mm = 0.5
flux_lm = 100.0

[holder]
min_mm = [0.0, 0.0, -6.0]
max_mm = [10.0, 10.0, 0.0]

[reflector]
family = "paraboloid"
fx = 3.0
fy = 3.0
z0 = -6.0
cx = 5.0
cy = 5.0
optimize = { fx = { min = 1.0, max = 5.0, step = 0.5 } }

[trace]
rays = 1000
max_bounces = 2
)";

struct BadCase {
    std::string replace; // a line of kBase (without newline)
    std::string with;
    std::string expect; // must appear in the message
};

// `base` with the case's edit, parsed as `file`: refused in one line that begins with the
// file's name and holds the expected words.
void expect_refused(const std::string& base, const BadCase& c, const std::string& file) {
    std::string text = base;
    const auto at = text.find(c.replace);
    ASSERT_NE(at, std::string::npos) << c.replace;
    text.replace(at, c.replace.size(), c.with);
    try {
        (void)parse_scene(text, file);
        ADD_FAILURE() << "accepted: " << c.with;
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(file, 0), 0u) << what;
        EXPECT_NE(what.find(c.expect), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
}

class BadScene : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadScene, IsRefusedWithFileKeyAndLine) {
    expect_refused(kBase, GetParam(), "bad.toml");
}

INSTANTIATE_TEST_SUITE_P(
    Table, BadScene,
    ::testing::Values(
        BadCase{"radius_mm = 0.5", "radius_mm = -0.5",
                "bad.toml:4: [source] radius_mm: must be > 0"},
        BadCase{"radius_mm = 0.5", "radius_mm = nan", "radius_mm: must be finite"},
        BadCase{"radius_mm = 0.5", "radius_mm = \"big\"", "radius_mm: must be a number"},
        BadCase{"radius_mm = 0.5", "radius = 0.5", "unknown key"},
        BadCase{"flux_lm = 100.0", "flux_lm = inf", "flux_lm: must be finite"},
        BadCase{"flux_lm = 100.0", "", "flux_lm: required key is missing"},
        BadCase{"type = \"sphere\"", "type = \"laser\"", "type: must be one of"},
        BadCase{"type = \"sphere\"",
                "type = \"disk\"\nnormal = [1.0, 0.0, 0.0]\nx_axis = [-2.0, 0.0, 0.0]",
                "x_axis: must not be parallel to the normal"},
        BadCase{"type = \"sphere\"", "type = \"disk\"\nnormal = [0.0, 0.0, 0.0]",
                "normal: must not be the zero vector"},
        BadCase{"type = \"sphere\"\ncenter_mm = [5.0, 5.0, -2.0]\nradius_mm = 0.5",
                "type = \"rectangle\"\ncenter_mm = [5.0, 5.0, -2.0]\nsize_mm = [1.0, 0.0]",
                "bad.toml:4: [source] size_mm: both sides must be > 0"},
        BadCase{"type = \"sphere\"\ncenter_mm = [5.0, 5.0, -2.0]\nradius_mm = 0.5",
                "type = \"rectangle\"\ncenter_mm = [5.0, 5.0, -2.0]\nradius_mm = 0.5",
                "[source] radius_mm: unknown key"},
        BadCase{"center_mm = [5.0, 5.0, -2.0]", "center_mm = [5.0, 5.0]",
                "center_mm: must be an array of 3"},
        BadCase{"center_mm = [5.0, 5.0, -2.0]", "center_mm = [50.0, 5.0, -2.0]",
                "outside the holder's xy footprint"},
        BadCase{"max_mm = [10.0, 10.0, 0.0]", "max_mm = [10.0, 10.0, -6.0]", "holder box is empty"},
        BadCase{"family = \"paraboloid\"", "family = \"blob\"", "family: must be one of"},
        BadCase{"fx = 3.0", "fx = -3.0", "'fx' must be > 0"},
        BadCase{"fy = 3.0", "", "[reflector] fy: required key is missing"},
        BadCase{"cy = 5.0", "cy = 5.0\nshape = 2", "[reflector] shape: unknown key"},
        BadCase{"z0 = -6.0", "z0 = -2.4", "cuts the light source"},
        BadCase{"optimize = { fx = { min = 1.0, max = 5.0, step = 0.5 } }",
                "optimize = { fx = { min = 6.0, max = 5.0, step = 0.5 } }",
                "max: must not be below min"},
        BadCase{"optimize = { fx = { min = 1.0, max = 5.0, step = 0.5 } }",
                "optimize = { fx = { min = 1.0, max = 5.0, step = 0.0 } }", "step: must be > 0"},
        BadCase{"optimize = { fx = { min = 1.0, max = 5.0, step = 0.5 } }",
                "optimize = { q = { min = 1.0, max = 5.0, step = 0.5 } }", "q: is not a parameter"},
        BadCase{"rays = 1000", "rays = 0", "rays: must be between"},
        BadCase{"rays = 1000", "rays = 1.5", "rays: must be an integer"},
        BadCase{"max_bounces = 2", "max_bounces = 0", "max_bounces: must be between"},
        BadCase{"max_bounces = 2", "max_bounces = 2\nbounce_policy = \"sometimes\"",
                "bounce_policy: must be one of"},
        BadCase{"max_bounces = 2", "max_bounces = 2\nfarfield = [0, 10]",
                "farfield: must be two whole numbers"},
        BadCase{"max_bounces = 2", "max_bounces = 2\n[target]\nparameters = { fx = 2.0 }\nseed = 1",
                "seed: must differ"},
        BadCase{"max_bounces = 2", "max_bounces = 2\n[target]\nparameters = { zz = 2.0 }",
                "zz: is not a parameter"},
        BadCase{"max_bounces = 2", "max_bounces = 2\n[target]\nseed = 4", "give either parameters"},
        BadCase{"[trace]", "[trace]\n[trace]", "redefine existing table 'trace'"},
        BadCase{"[trace]", "[reflector.material]\nreflectance = 1.2\n[trace]",
                "bad.toml:21: [reflector.material] reflectance: must be between 0 and 1"},
        BadCase{"[trace]", "[reflector.material]\nspread_deg = -1\n[trace]",
                "[reflector.material] spread_deg: must be between 0 and 30 degrees"},
        BadCase{"[trace]", "[reflector.material]\nspread_deg = 45.0\n[trace]",
                "spread_deg: must be between 0 and 30 degrees"},
        BadCase{"[trace]", "[reflector.material]\nlobe = \"lambert\"\n[trace]",
                "[reflector.material] lobe: must be one of: gaussian, phong"},
        BadCase{"[trace]", "[reflector.material]\nroughness = 0.1\n[trace]",
                "[reflector.material] roughness: unknown key"},
        BadCase{"radius_mm = 0.5",
                "radius_mm = 0.5\noptimize = { w_mm = { min = 0.0, max = 1.0, step = 0.5 } }",
                "[source.optimize] w_mm: is not a source parameter"},
        BadCase{
            "radius_mm = 0.5",
            "radius_mm = 0.5\noptimize = { tilt_x_deg = { min = 0.0, max = 10.0, step = 5.0 } }",
            "tilt_x_deg: a sphere source has no axis to tilt"},
        BadCase{"radius_mm = 0.5",
                "radius_mm = 0.5\noptimize = { z_mm = { min = 0.0, max = -1.0, step = 0.5 } }",
                "[source.optimize.z_mm] max: must not be below min"},
        BadCase{"max_bounces = 2", "max_bounces = 2\ndirect = \"both\"",
                "[trace] direct: must be one of: exclude, include"},
        BadCase{"[trace]", "[reflector.constraints]\nmax_slope_deg = 90.0\n[trace]",
                "bad.toml:21: [reflector.constraints] max_slope_deg: must be between 0 and 90"},
        BadCase{"[trace]", "[reflector.constraints]\nmin_radius_mm = 0\n[trace]",
                "bad.toml:21: [reflector.constraints] min_radius_mm: must be > 0"},
        BadCase{"[trace]", "[reflector.constraints]\nmax_depth_mm = \"deep\"\n[trace]",
                "[reflector.constraints] max_depth_mm: must be a number"},
        BadCase{"[trace]", "[reflector.constraints]\nmax_draft = 5.0\n[trace]",
                "[reflector.constraints] max_draft: unknown key"},
        BadCase{"max_bounces = 2", "max_bounces = 2\n[optimize]\nsmoothness = -0.5",
                "[optimize] smoothness: must be >= 0"},
        BadCase{"max_bounces = 2", "max_bounces = 2\n[optimize]\nsmoothness = \"high\"",
                "[optimize] smoothness: must be a number"},
        BadCase{"fx = 3.0", "fx = 3.0 3.0", "bad.toml:13"}));

// [optimize] smoothness: read, written back, and refused for a mesh (its flat facets have
// no curvature: the penalty would be the grid's, not the part's) in one line naming it.
TEST(SceneFile, ASmoothnessWeightReadsRoundTripsAndIsRefusedForAMesh) {
    const Scene plain = parse_scene(kPointSource + kAfterSource, "plain.toml");
    EXPECT_EQ(plain.optimize.smoothness, 0.0);
    EXPECT_EQ(scene_to_toml(plain).find("smoothness"), std::string::npos);
    const Scene s =
        parse_scene(kPointSource + kAfterSource + "[optimize]\nsmoothness = 2.5\n", "smooth.toml");
    EXPECT_EQ(s.optimize.smoothness, 2.5);
    EXPECT_EQ(parse_scene(scene_to_toml(s), "smooth.toml"), s);
    const std::string mesh_path = kScenes + "test/mesh_dish.toml";
    std::ifstream in(mesh_path);
    const std::string mesh((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(mesh.empty());
    try {
        (void)parse_scene(mesh + "\n[optimize]\nsmoothness = 1.0\n", mesh_path);
        ADD_FAILURE() << "a mesh with a smoothness weight was accepted";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(what.rfind(mesh_path, 0), 0u) << what;
        EXPECT_NE(what.find("[optimize] smoothness: a mesh's flat facets"), std::string::npos)
            << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// A B-spline whose every control height is freed by one line: bad values of heights_mm
// (in [reflector] or in [reflector.optimize]) are refused in one line naming the key.
TEST(SceneFile, FreeingEveryControlHeightRefusesBadInputNamingTheKey) {
    const std::string base = R"(
[source]
type = "point"
center_mm = [0.0, 0.0, -1.0]
flux_lm = 100.0
[holder]
min_mm = [-20.0, -20.0, -12.0]
max_mm = [20.0, 20.0, 0.0]
[reflector]
family = "bspline"
grid = [3, 2]
heights_mm = -6.0
[reflector.optimize]
heights_mm = { min = -10.0, max = -2.0, step = 0.5 }
[trace]
rays = 1000
max_bounces = 1
)";
    const Scene s = parse_scene(base, "free.toml");
    EXPECT_EQ(s.reflector.bspline.heights_mm, std::vector<double>(6, -6.0));
    ASSERT_EQ(s.reflector.optimize.size(), 6u);
    EXPECT_EQ(s.reflector.optimize.at("h_2_1"), (ParameterRange{-10.0, -2.0, 0.5}));
    EXPECT_EQ(s.reflector.bspline.groups.at("h_2_1"),
              (ControlGroup{.kind = ControlGroup::Kind::Point, .i = 2, .j = 1}));
    EXPECT_FALSE(s.reflector.optimize.contains("h_3_0")); // 3 columns: i in 0..2
    EXPECT_FALSE(s.reflector.optimize.contains("h_0_2")); // 2 rows: j in 0..1
    const std::vector<BadCase> bad{
        {"heights_mm = -6.0", "heights_mm = \"flat\"",
         "free.toml:12: [reflector] heights_mm: must be one number (every control height) or an "
         "array of 6 numbers"},
        {"heights_mm = -6.0", "heights_mm = [-6.0, -6.0]",
         "[reflector] heights_mm: must be an array of 6 numbers"},
        {"heights_mm = { min = -10.0, max = -2.0, step = 0.5 }",
         "heights_mm = { min = -1.0, max = -2.0, step = 0.5 }",
         "[reflector.optimize.heights_mm] max: must not be below min"},
        {"heights_mm = { min = -10.0, max = -2.0, step = 0.5 }",
         "heights_mm = { min = -10.0, max = -2.0 }",
         "[reflector.optimize.heights_mm] step: required key is missing"},
        {"heights_mm = { min = -10.0, max = -2.0, step = 0.5 }",
         "heights_mm = { min = -10.0, max = -2.0, step = 0.5 }\n[reflector.groups]\nrim = { kind "
         "= \"ring\", index = 0 }",
         "[reflector.optimize] heights_mm: frees every control height, so it cannot be combined "
         "with [reflector.groups]"},
        {"family = \"bspline\"\ngrid = [3, 2]\nheights_mm = -6.0",
         "family = \"paraboloid\"\nfx = 3.0\nfy = 3.0\nz0 = -6.0\ncx = 0.0\ncy = 0.0",
         "[reflector.optimize] heights_mm: is not a parameter of the paraboloid family"}};
    for (const BadCase& c : bad)
        expect_refused(base, c, "free.toml");
}

// The profile family's heights: read from an array or one number with its count, each a
// parameter h_<k>; bad input refused naming the key.
TEST(SceneFile, AProfilesHeightsAreParametersAndBadInputIsRefusedNamingTheKey) {
    const std::string base = R"(
[source]
type = "point"
center_mm = [0.0, 0.0, -1.0]
flux_lm = 100.0
[holder]
min_mm = [-20.0, -20.0, -12.0]
max_mm = [20.0, 20.0, 0.0]
[reflector]
family = "profile"
z0 = -8.0
cx = 0.0
cy = 0.0
radius_mm = 15.0
heights_mm = 1.0
grid = 4
h_2 = 1.5
[reflector.optimize]
heights_mm = { min = 0.0, max = 6.0, step = 0.5 }
[trace]
rays = 1000
max_bounces = 1
)";
    const Scene s = parse_scene(base, "profile.toml");
    EXPECT_EQ(s.reflector.bspline.heights_mm, std::vector<double>(4, 1.0));
    EXPECT_EQ(s.reflector.bspline.ny, 1);
    EXPECT_EQ(s.reflector.parameters.at("h_2"), 1.5);
    ASSERT_EQ(s.reflector.optimize.size(), 4u);
    EXPECT_EQ(s.reflector.optimize.at("h_3"), (ParameterRange{0.0, 6.0, 0.5}));
    const std::vector<BadCase> bad{
        {"grid = 4\n", "", "[reflector] heights_mm: is one number, so `grid` must give"},
        {"heights_mm = 1.0\ngrid = 4", "heights_mm = [1.0]",
         "[reflector] heights_mm: must hold between 2 and 1024 heights"},
        {"heights_mm = 1.0\ngrid = 4", "heights_mm = [1.0, 2.0, 3.0]\ngrid = 4",
         "[reflector] grid: must equal the number of heights_mm"},
        {"radius_mm = 15.0", "radius_mm = 0.0", "[reflector] radius_mm: must be > 0"},
        {"heights_mm = { min = 0.0, max = 6.0, step = 0.5 }",
         "heights_mm = { min = 0.0, max = 6.0, step = 0.5 }\nh_1 = { min = 0.0, max = 2.0, step "
         "= 0.5 }",
         "[reflector.optimize] heights_mm: frees every height, so it cannot be combined with h_1"}};
    for (const BadCase& c : bad)
        expect_refused(base, c, "profile.toml");
}

TEST(SceneFile, MissingFileIsAClearError) {
    EXPECT_THROW((void)load_scene("/nonexistent/scene.toml"), SceneError);
}

} // namespace
} // namespace fird
