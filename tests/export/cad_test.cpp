// fird export --cad read back by readers that are not the writer: reflector.step meshed by
// gmsh (Debian's, through its own STEP import and mesher), reflector.stl by the small
// reader here; heights against the family's own function, closedness, outward facets,
// the sheet's volume against thickness x area, and each bad input refused.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <unistd.h>

#include <GeomLProp_SLProps.hxx>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "app/run_fird.hpp"
#include "export/cad_curvature.hpp"
#include "export/cad_surface.hpp"
#include "io/scene_file.hpp"
#include "model/press_measures.hpp"
#include "model/surface.hpp"

namespace fird::test {
namespace {

namespace fs = std::filesystem;

std::string dir(const std::string& name) {
    const fs::path p =
        fs::path(::testing::TempDir()) / ("fird_cad_" + name + "." + std::to_string(::getpid()));
    fs::remove_all(p);
    return p.string();
}

std::string source(const char* relative) {
    return std::string(FIRD_SOURCE_DIR) + "/" + relative;
}

Surface surface_of(const std::string& scene_path) {
    const Scene s = load_scene(scene_path);
    return Surface::make(s.reflector, s.holder);
}

Result fird(const std::string& args) {
    return run_fird("timeout 300", args);
}

// A dome (the cup family with h < 0 and p = 2): z = -2 - ((x-5)/5)^2 - ((y-5)/6)^2 over
// 10 x 10 mm, nowhere clamped. Its smallest radius of curvature, bending away from the
// normal, is at the apex along x: a^2 / (2 |h|) = 12.5 mm.
constexpr double kDomeRadiusMm = 12.5;
// (h = +1: the same as a bowl, concave up.)
std::string dome_scene(const std::string& h = "-1.0") {
    const std::string path = dir("dome" + h) + ".toml";
    std::ofstream(path) << R"(name = "dome"
[source]
type = "point"
center_mm = [5.0, 5.0, 2.0]
emittance = "isotropic"
flux_lm = 100.0
[holder]
min_mm = [0.0, 0.0, -10.0]
max_mm = [10.0, 10.0, 4.0]
[reflector]
family = "cup"
a = 5.0
b = 6.0
p = 2.0
h = )" + h + R"(
z0 = -2.0
cx = 5.0
cy = 5.0
[trace]
rays = 10000
seed = 1
max_bounces = 1
farfield = [36, 18]
heightfield = [40, 40]
)";
    return path;
}

// gmsh's mesh of a STEP file (MSH 2 text): nodes, and the tetrahedra when meshed in 3D.
struct GmshMesh {
    std::vector<glm::dvec3> nodes;
    std::vector<std::array<std::size_t, 4>> tetrahedra;
};

GmshMesh gmsh_mesh(const std::string& step, int dimension) {
    const std::string msh = step + ".msh";
    // -clmax 1: elements of at most 1 mm (gmsh's default scales with the part's size).
    const std::string cmd = "gmsh -" + std::to_string(dimension) + " -clmax 1 " + step +
                            " -format msh2 -o " + msh + " > " + msh + ".log 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
    std::ifstream in(msh);
    GmshMesh m;
    std::string line;
    std::map<long, std::size_t> index;
    while (std::getline(in, line)) {
        if (line == "$Nodes") {
            std::size_t n = 0;
            in >> n;
            for (std::size_t k = 0; k < n; ++k) {
                long id;
                glm::dvec3 p;
                in >> id >> p.x >> p.y >> p.z;
                index[id] = m.nodes.size();
                m.nodes.push_back(p);
            }
        } else if (line == "$Elements") {
            std::size_t n = 0;
            in >> n;
            std::getline(in, line);
            for (std::size_t k = 0; k < n; ++k) {
                std::getline(in, line);
                std::istringstream e(line);
                long id, type, tags;
                e >> id >> type >> tags;
                for (long t = 0; t < tags; ++t)
                    e >> id;
                if (type != 4) continue; // 4-node tetrahedron
                std::array<std::size_t, 4> t{};
                for (auto& v : t) {
                    long node;
                    e >> node;
                    v = index.at(node);
                }
                m.tetrahedra.push_back(t);
            }
        }
    }
    return m;
}

// fird export SCENE --cad DIR OPTIONS, then gmsh's mesh of its STEP file in `dimension`.
struct Exported {
    Result run;
    GmshMesh mesh;
};
Exported export_and_mesh(const std::string& name, const std::string& scene,
                         const std::string& options, int dimension) {
    const std::string out = dir(name);
    Exported e{fird("export " + scene + " --cad " + out + " " + options), {}};
    if (e.run.code == 0) e.mesh = gmsh_mesh(out + "/reflector.step", dimension);
    return e;
}

// A binary STL: facets with their stored normal.
struct Facet {
    glm::dvec3 normal;
    std::array<glm::dvec3, 3> v;
};

std::vector<Facet> read_stl(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_GE(bytes.size(), 84u);
    std::uint32_t n = 0;
    std::memcpy(&n, bytes.data() + 80, 4);
    EXPECT_EQ(bytes.size(), 84u + 50u * n) << "size against the facet count";
    std::vector<Facet> facets(n);
    const auto vec = [&](std::size_t at) {
        float f[3];
        std::memcpy(f, bytes.data() + at, 12);
        return glm::dvec3(f[0], f[1], f[2]);
    };
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t at = 84 + 50 * k;
        facets[k].normal = vec(at);
        for (int i = 0; i < 3; ++i)
            facets[k].v[std::size_t(i)] = vec(at + 12 + 12 * std::size_t(i));
    }
    return facets;
}

// The largest normal curvature the family can have: the Hessian's largest absolute
// eigenvalue bounds it (Gershgorin: max row sum of |f_xx| + |f_xy|, |f_xy| + |f_yy|),
// from central differences of the analytic gradient on a grid.
double max_curvature(const Surface& f) {
    const Holder& h = f.holder();
    const double e = 1e-4;
    double worst = 0.0;
    for (int i = 1; i < 100; ++i)
        for (int j = 1; j < 100; ++j) {
            const double x = h.min_mm.x + (h.max_mm.x - h.min_mm.x) * i / 100.0;
            const double y = h.min_mm.y + (h.max_mm.y - h.min_mm.y) * j / 100.0;
            const glm::dvec2 gx = (f.gradient(x + e, y) - f.gradient(x - e, y)) / (2 * e);
            const glm::dvec2 gy = (f.gradient(x, y + e) - f.gradient(x, y - e)) / (2 * e);
            worst =
                std::max({worst, std::abs(gx.x) + std::abs(gx.y), std::abs(gy.x) + std::abs(gy.y)});
        }
    return worst;
}

// The surface's area, by the midpoint rule on sqrt(1 + |grad f|^2) over 400 x 400 cells.
double area(const Surface& f) {
    const Holder& h = f.holder();
    const double dx = (h.max_mm.x - h.min_mm.x) / 400, dy = (h.max_mm.y - h.min_mm.y) / 400;
    double a = 0.0;
    for (int i = 0; i < 400; ++i)
        for (int j = 0; j < 400; ++j) {
            const glm::dvec2 g =
                f.gradient(h.min_mm.x + (i + 0.5) * dx, h.min_mm.y + (j + 0.5) * dy);
            a += std::sqrt(1.0 + glm::dot(g, g)) * dx * dy;
        }
    return a;
}

// The relative bound on |V / (t A) - 1| for a sheet offset by t along the normal: Steiner's
// formula V = t A - t^2 int H + t^3 int K / 3 with |H| <= k, |K| <= k^2 (k the largest
// curvature), plus 1 % for the flat facets' and the midpoint rule's error on A.
double volume_bound(double t, double k) {
    return t * k + t * t * k * k / 3.0 + 0.01;
}

TEST(CadSurface, BSplineFamilyIsTheSameSplineToRounding) {
    const Surface f = surface_of(source("scenes/test/bspline_dish.toml"));
    const CadSurface cad = make_cad_surface(f, 0.01);
    ASSERT_TRUE(cad.exact);
    // 10^4 random points: the CAD spline (OCCT's de Boor) against the family's own basis
    // sums; both sum 16 products of heights <= 6 mm, so 1e-12 mm bounds double rounding.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 10.0);
    double worst = 0.0;
    for (int k = 0; k < 10000; ++k) {
        const double x = u(rng), y = u(rng);
        const gp_Pnt p = cad.surface->Value(x, y);
        EXPECT_NEAR(p.X(), x, 1e-12) << "u is x";
        EXPECT_NEAR(p.Y(), y, 1e-12) << "v is y";
        worst = std::max(worst, std::abs(p.Z() - f.height(x, y)));
    }
    EXPECT_LT(worst, 1e-12);
}

TEST(CadSurface, DomeSmallestBackRadiusIsTheApexRadius) {
    const Surface f = surface_of(dome_scene());
    const CadSurface cad = make_cad_surface(f, 0.001);
    EXPECT_FALSE(cad.exact);
    EXPECT_LE(cad.max_deviation_mm, 0.001);
    // The fit's curvature at the apex against a^2 / (2|h|): an interpolating cubic of a
    // quadratic reproduces it (the clamped spline is exact on cubics) up to rounding; 0.1 %
    // for the grid missing the apex by up to a sampling step (the radius grows as
    // (1 + z'^2)^(3/2), z' <= 0.4 * step / 5 there).
    const BackCurvature back = smallest_back_radius(cad.surface, 201, 201);
    EXPECT_NEAR(back.smallest_radius_mm, kDomeRadiusMm, 1e-3 * kDomeRadiusMm);
    EXPECT_NEAR(back.where_xy_mm.x, 5.0, 0.05);
    // The bowl (concave up) never bends back.
    const Surface bowl = surface_of(dome_scene("1.0"));
    EXPECT_TRUE(std::isinf(
        smallest_back_radius(make_cad_surface(bowl, 0.01).surface, 101, 101).smallest_radius_mm));
}

// The press's curvature (differences of the family's gradient, model/press_measures.hpp)
// against OpenCASCADE's principal curvatures of the exact CAD spline, an independent
// evaluation, at every sample of a 94 x 94 grid: its samples miss the knots (x every 2 mm,
// y every 2.5 mm) by more than the difference step, so each difference is of one piece of
// the gradient, a quadratic, which central and one-sided second-order differences take
// exactly; what is left is rounding (1e-9 per mm) and the map's float (1e-6 relative).
TEST(CadSurface, ThePressCurvatureIsOpenCascadesOnTheExactSpline) {
    const Surface f = surface_of(source("scenes/test/bspline_dish.toml"));
    const CadSurface cad = make_cad_surface(f, 0.01);
    ASSERT_TRUE(cad.exact);
    const PressMeasures m = press_measures(f, 94, 94, {.maps = true});
    GeomLProp_SLProps props(cad.surface, 2, 1e-9);
    double largest = 0.0;
    for (int j = 0; j < m.ny; ++j)
        for (int i = 0; i < m.nx; ++i) {
            props.SetParameters(i * m.dx_mm, j * m.dy_mm);
            ASSERT_TRUE(props.IsCurvatureDefined());
            const double k =
                std::max(std::abs(props.MinCurvature()), std::abs(props.MaxCurvature()));
            largest = std::max(largest, k);
            ASSERT_NEAR(m.maps.curvature_per_mm[std::size_t(j) * m.nx + i], k, 1e-9 + 1e-6 * k)
                << i << "," << j;
        }
    EXPECT_NEAR(m.min_radius_mm, 1.0 / largest, 1e-9 * m.min_radius_mm);
}

TEST(CadStep, GmshReadsTheBSplineExactly) {
    const std::string scene = source("scenes/test/bspline_dish.toml");
    const auto [r, m] = export_and_mesh("step_bspline", scene, "", 2);
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_GT(m.nodes.size(), 50u);
    const Surface f = surface_of(scene);
    // gmsh puts its nodes on the surface it read and writes 13 significant digits: x, y
    // rounded by 1e-12 mm times slopes under 3, so 1e-9 mm bounds the exact spline's gap.
    double worst = 0.0;
    for (const glm::dvec3& p : m.nodes) {
        EXPECT_GE(p.x, -1e-9);
        EXPECT_LE(p.x, 10.0 + 1e-9);
        worst = std::max(worst, std::abs(p.z - f.height(p.x, p.y)));
    }
    EXPECT_LT(worst, 1e-9) << "over " << m.nodes.size() << " nodes";
}

TEST(CadStep, GmshMeshesTheSheetWithThicknessTimesArea) {
    const std::string scene = source("scenes/test/bspline_dish.toml");
    const double t = 0.5;
    const auto [r, m] = export_and_mesh("step_sheet", scene, "--thickness 0.5", 3);
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_GT(m.tetrahedra.size(), 100u);
    double volume = 0.0;
    for (const auto& k : m.tetrahedra) {
        const glm::dvec3 a = m.nodes[k[0]];
        volume += std::abs(glm::dot(m.nodes[k[1]] - a,
                                    glm::cross(m.nodes[k[2]] - a, m.nodes[k[3]] - a))) /
                  6.0;
    }
    const Surface f = surface_of(scene);
    const double expected = t * area(f);
    EXPECT_NEAR(volume / expected, 1.0, volume_bound(t, max_curvature(f)));
}

// Undirected edges of the facets, by their float coordinates as written, and in which
// directions the facets run along them.
std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, std::array<int, 2>>
edges(const std::vector<Facet>& facets) {
    std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, std::array<int, 2>> e;
    const auto key = [](const glm::dvec3& p) {
        return std::array<float, 3>{float(p.x), float(p.y), float(p.z)};
    };
    for (const Facet& t : facets)
        for (int k = 0; k < 3; ++k) {
            const auto a = key(t.v[std::size_t(k)]), b = key(t.v[std::size_t((k + 1) % 3)]);
            auto& count = a < b ? e[{a, b}] : e[{b, a}];
            ++count[a < b ? 0 : 1];
        }
    return e;
}

TEST(CadStl, SheetIsClosedFacesOutAndHasThicknessTimesArea) {
    const std::string out = dir("stl_sheet");
    const std::string scene = source("scenes/test/bspline_dish.toml");
    const double t = 0.5;
    const Result r = fird("export " + scene + " --cad " + out + " --thickness 0.5");
    ASSERT_EQ(r.code, 0) << r.out;
    const std::vector<Facet> facets = read_stl(out + "/reflector.stl");
    ASSERT_GT(facets.size(), 1000u);
    // Closed and consistently wound: every edge in exactly two facets, once each way.
    for (const auto& [edge, runs] : edges(facets))
        ASSERT_TRUE(runs[0] == 1 && runs[1] == 1) << "an edge used " << runs[0] << " + " << runs[1];
    // Outward: the divergence theorem's signed volume is positive and is t A (Steiner's
    // bound as above); the stored normals agree with the winding.
    double volume = 0.0;
    for (const Facet& k : facets) {
        volume += glm::dot(k.v[0], glm::cross(k.v[1], k.v[2])) / 6.0;
        const glm::dvec3 c = glm::cross(k.v[1] - k.v[0], k.v[2] - k.v[0]);
        if (glm::length(c) > 1e-9) {
            EXPECT_GT(glm::dot(glm::normalize(c), k.normal), 0.999);
        }
    }
    const Surface f = surface_of(scene);
    EXPECT_NEAR(volume / (t * area(f)), 1.0, volume_bound(t, max_curvature(f)));
    // The top lies on the family: the exact spline, to float rounding of coordinates
    // under 10 mm (6e-7 mm) times slopes under 3. The top facets are those within 0.1 mm
    // of it (the back lies t = 0.5 mm below, the walls join the two): all 2 x 128 x 128 of
    // the report's 129 x 129 samples must be found there.
    ASSERT_NE(r.out.find("STL: 129 x 129 samples"), std::string::npos) << r.out;
    std::size_t top = 0;
    for (const Facet& k : facets) {
        bool on = true;
        for (const glm::dvec3& p : k.v)
            on = on && std::abs(p.z - f.height(p.x, p.y)) < 0.1;
        if (!on) continue;
        ++top;
        EXPECT_GT(k.normal.z, 0.0);
        for (const glm::dvec3& p : k.v)
            EXPECT_NEAR(p.z, f.height(p.x, p.y), 3e-6);
    }
    EXPECT_EQ(top, 2u * 128u * 128u);
}

// The crease edges' tolerance the export reports (OpenCASCADE's, of the intersection
// curves where the family meets the holder's top or floor).
double crease_tolerance(const std::string& out) {
    const std::string key = "crease edges within ";
    const auto at = out.find(key);
    EXPECT_NE(at, std::string::npos) << out;
    return at == std::string::npos ? 0.0 : std::stod(out.substr(at + key.size()));
}

// How far a point on a clamped model's CAD shell may lie from the family: the fit's
// tolerance (met on the check grid: see SmoothFitsAreWithinTheToleranceBetweenCheckPoints
// for between them), and on a crease edge its tolerance E (a distance to each face) seen
// vertically, E sqrt(1 + |grad f|^2); E is printed to two digits, hence 1.05.
// E is first held to the fit's tolerance, a cap that does not come from the export: the
// bound then cannot grow with a bad intersection (measured: 5e-6 mm on A and B, 4e-4 on C).
double clamped_bound(const std::string& out, double tolerance, double slope) {
    const double edge = crease_tolerance(out);
    EXPECT_LE(edge, tolerance) << "a crease edge strays from its faces";
    return tolerance + 1.05 * edge * std::sqrt(1.0 + slope * slope);
}

class CreasedModel : public ::testing::TestWithParam<const char*> {};

TEST_P(CreasedModel, GmshReadsTheTrimmedSurfaceAndTheFlangeOnTheFamily) {
    const std::string scene = source(GetParam());
    const auto [r, m] = export_and_mesh("creased", scene, "", 2);
    ASSERT_EQ(r.code, 0) << r.out;
    ASSERT_NE(r.out.find("the family without its clamp"), std::string::npos) << r.out;
    ASSERT_GT(m.nodes.size(), 50u);
    const Surface f = surface_of(scene);
    const double top = f.holder().max_mm.z;
    double slope = 0.0;
    for (const glm::dvec3& p : m.nodes)
        if (f.raw(p.x, p.y) < top) slope = std::max(slope, glm::length(f.raw_gradient(p.x, p.y)));
    const double bound = clamped_bound(r.out, 0.01, slope);
    double worst = 0.0;
    std::size_t flange = 0;
    for (const glm::dvec3& p : m.nodes) {
        worst = std::max(worst, std::abs(p.z - f.height(p.x, p.y)));
        flange += f.raw(p.x, p.y) > top + 0.01;
    }
    EXPECT_LE(worst, bound) << "over " << m.nodes.size() << " nodes";
    EXPECT_GT(flange, 10u) << "gmsh meshed the flange too";
    std::printf("%s: gmsh's %zu nodes within %.2g mm of the family (bound %.2g mm)\n", GetParam(),
                m.nodes.size(), worst, bound);
}

TEST_P(CreasedModel, StlFacesUpOnTheFamilyAndOpenOnlyAtTheHolderRim) {
    const std::string out = dir("creased_stl");
    const std::string scene = source(GetParam());
    const Result r = fird("export " + scene + " --cad " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::vector<Facet> facets = read_stl(out + "/reflector.stl");
    ASSERT_GT(facets.size(), 100u);
    const Surface f = surface_of(scene);
    const Holder& h = f.holder();
    // The vertices lie on the CAD faces (float rounding: 1e-5 mm at coordinates under 30
    // mm times slopes under 4), so within the fit's and the crease's bound of the family.
    double slope = 0.0;
    for (const Facet& k : facets)
        for (const glm::dvec3& p : k.v)
            if (f.raw(p.x, p.y) < h.max_mm.z)
                slope = std::max(slope, glm::length(f.raw_gradient(p.x, p.y)));
    const double bound = clamped_bound(r.out, 0.01, slope) + 1e-5;
    for (const Facet& k : facets) {
        EXPECT_GT(k.normal.z, 0.0) << "the reflecting side faces up";
        for (const glm::dvec3& p : k.v)
            EXPECT_NEAR(p.z, f.height(p.x, p.y), bound);
    }
    // Watertight across the creases: an edge in one facet lies on the holder's rim, every
    // other edge is in two facets, once each way.
    const auto on_rim = [&](const std::array<float, 3>& p) {
        const double e = 1e-4; // float rounding of coordinates under 30 mm
        return std::abs(p[0] - h.min_mm.x) < e || std::abs(p[0] - h.max_mm.x) < e ||
               std::abs(p[1] - h.min_mm.y) < e || std::abs(p[1] - h.max_mm.y) < e;
    };
    for (const auto& [edge, runs] : edges(facets)) {
        if (runs[0] + runs[1] == 1) {
            EXPECT_TRUE(on_rim(edge.first) && on_rim(edge.second)) << "an open edge inside";
        } else {
            EXPECT_TRUE(runs[0] == 1 && runs[1] == 1) << runs[0] << " + " << runs[1];
        }
    }
}

INSTANTIATE_TEST_SUITE_P(ModelsABC, CreasedModel,
                         ::testing::Values("scenes/model_a.toml", "scenes/model_b.toml",
                                           "scenes/model_c.toml"));

// A smooth family fitted whole (the dome: nothing clamps): the deviation between check
// points against random points, to the fourth-order rest the check grid leaves.
TEST(CadSurface, SmoothFitsAreWithinTheToleranceBetweenCheckPoints) {
    const Surface f = surface_of(dome_scene("1.0"));
    for (const double tolerance : {1e-3, 1e-6}) {
        const CadSurface cad = make_cad_surface(f, tolerance);
        ASSERT_LE(cad.max_deviation_mm, tolerance);
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(0.0, 10.0);
        double worst = 0.0;
        for (int k = 0; k < 20000; ++k) {
            const double x = u(rng), y = u(rng);
            worst = std::max(worst, std::abs(cad.surface->Value(x, y).Z() - f.height(x, y)));
        }
        EXPECT_LE(worst, tolerance) << cad.fit_nx << " x " << cad.fit_ny;
    }
}

bool has_cad_files(const std::string& d) {
    if (!fs::exists(d)) return false;
    for (const auto& e : fs::directory_iterator(d))
        if (e.path().filename().string().find("reflector") != std::string::npos) return true;
    return false;
}

TEST(CadBadInput, ThicknessAtTheRadiusIsRefusedNamingTheOption) {
    const std::string scene = dome_scene();
    const std::string out = dir("bad_thickness");
    const Result r = fird("export " + scene + " --cad " + out + " --thickness 12.6");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("fird: error: --thickness 12.6"), std::string::npos) << r.out;
    EXPECT_FALSE(has_cad_files(out)) << "nothing written";
    // Just under the radius the sheet is made.
    const Result ok = fird("export " + scene + " --cad " + out + " --thickness 12");
    EXPECT_EQ(ok.code, 0) << ok.out;
    // A clamped model's crease would need a bend radius: any sheet is refused.
    const std::string creased = dir("bad_thickness_creased");
    const Result c =
        fird("export " + source("scenes/model_a.toml") + " --cad " + creased + " --thickness 0.1");
    EXPECT_EQ(c.code, 2) << c.out;
    EXPECT_NE(c.out.find("fird: error: --thickness 0.1: the reflector meets the holder's top in "
                         "a crease"),
              std::string::npos)
        << c.out;
    EXPECT_FALSE(has_cad_files(creased));
}

TEST(CadBadInput, UnreachableToleranceIsRefusedNamingTheOption) {
    const std::string out = dir("bad_tolerance");
    const Result r = fird("export " + source("scenes/test/mesh_dish.toml") + " --cad " + out +
                          " --cad-tolerance 1e-7");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("fird: error: --cad-tolerance 1e-07 mm"), std::string::npos) << r.out;
    EXPECT_FALSE(has_cad_files(out));
    // Not numbers, or out of range (a tolerance must be > 0 mm, a thickness >= 0 mm).
    const auto refused = [&](const std::string& option, const char* value) {
        const Result b = fird("export " + source("scenes/test/bspline_dish.toml") + " --cad " +
                              out + " " + option + " " + value);
        EXPECT_EQ(b.code, 2) << b.out;
        EXPECT_NE(b.out.find(option), std::string::npos) << b.out;
    };
    for (const char* bad : {"0", "-1", "nan", "x"})
        refused("--cad-tolerance", bad);
    for (const char* bad : {"-1", "nan", "x"})
        refused("--thickness", bad);
    EXPECT_FALSE(has_cad_files(out));
}

TEST(CadBadInput, UnwritableDirectoryIsARuntimeErrorNamingIt) {
    const std::string blocker = dir("blocker");
    std::ofstream(blocker) << "x";
    const Result r =
        fird("export " + source("scenes/test/bspline_dish.toml") + " --cad " + blocker + "/cad");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(blocker + "/cad: cannot create the output directory"), std::string::npos)
        << r.out;
}

} // namespace
} // namespace fird::test
