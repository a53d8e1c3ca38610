// Triangle-mesh reflectors: OBJ and STL readers, the height-field (graph) check, and the
// reference tracer's exact intersection with the triangles.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "model/mesh.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {
namespace {

std::string temp(const std::string& name) {
    return ::testing::TempDir() + "/" + name;
}

void write(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
}

// An n x n grid of vertices over [x0, x1] x [y0, y1] with z = f(x, y), two triangles a cell.
template <typename F> std::string grid_obj(int n, double x0, double x1, double y0, double y1, F f) {
    std::string s = "# test grid\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = x0 + (x1 - x0) * i / (n - 1), y = y0 + (y1 - y0) * j / (n - 1);
            s += "v " + std::to_string(x) + " " + std::to_string(y) + " " +
                 std::to_string(f(x, y)) + "\n";
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
            s +=
                "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + "\n";
            s += "f " + std::to_string(a) + "/1/1 " + std::to_string(d) + " " + std::to_string(c) +
                 "\n";
        }
    return s;
}

std::string mesh_scene(const std::string& file, double unit = 1.0) {
    return R"([source]
type = "point"
center_mm = [0.0, 0.0, 5.0]
flux_lm = 100.0
[holder]
min_mm = [-20.0, -20.0, -10.0]
max_mm = [20.0, 20.0, 4.0]
[reflector]
family = "mesh"
file = ")" +
           file + R"("
unit_mm = )" +
           std::to_string(unit) + R"(
[trace]
rays = 1000
max_bounces = 1
)";
}

TEST(Mesh, TessellatedTiltedPlaneReflectsExactlyLikeThePlane) {
    const std::string obj = temp("plane.obj");
    write(obj, grid_obj(9, -20, 20, -20, 20,
                        [](double x, double y) { return -2.0 + 0.2 * x - 0.1 * y; }));
    const Scene s = parse_scene(mesh_scene(obj), temp("plane.toml"));
    const Surface surface = Surface::make(s.reflector, s.holder);
    const glm::dvec3 n = glm::normalize(glm::dvec3(-0.2, 0.1, 1.0));
    int reflected = 0;
    for (std::uint64_t i = 0; i < 5000; ++i) {
        const Ray ray = emit_ray(s.source, SamplerKind::Random, 3, i, 5000);
        std::vector<glm::dvec3> path;
        const PathResult r = trace_path(surface, s.holder, ray, 1, BouncePolicy::Strict, &path);
        if (r.fate != RayFate::FarField) continue;
        ++reflected;
        ASSERT_NEAR(
            glm::length(r.direction - (ray.direction - 2.0 * glm::dot(ray.direction, n) * n)), 0.0,
            1e-6);
        ASSERT_NEAR(path[1].z, -2.0 + 0.2 * path[1].x - 0.1 * path[1].y, 1e-6);
    }
    EXPECT_GT(reflected, 1000);
}

TEST(Mesh, TessellatedParaboloidConvergesToTheAnalyticFarField) {
    const auto f = [](double x, double y) { return std::min(4.0, -8.0 + (x * x + y * y) / 12.0); };
    const std::string obj = temp("dish.obj");
    write(obj, grid_obj(161, -20, 20, -20, 20, f));
    const Scene s = parse_scene(mesh_scene(obj), temp("dish.toml"));
    Scene analytic = s;
    analytic.reflector = {
        .family = Family::Paraboloid,
        .parameters = {{"fx", 3.0}, {"fy", 3.0}, {"z0", -8.0}, {"cx", 0.0}, {"cy", 0.0}}};
    const ReferenceOptions o{
        .rays = 200000, .seed = 4, .max_bounces = 1, .farfield_w = 90, .farfield_h = 45};
    const auto mesh_run = trace_reference(s.source, Surface::make(s.reflector, s.holder), o);
    const auto exact_run =
        trace_reference(s.source, Surface::make(analytic.reflector, s.holder), o);
    // Same rays: the difference is the tessellation's alone, and small against the flux.
    EXPECT_LT(l2_distance(mesh_run.farfield, exact_run.farfield),
              0.02 * exact_run.farfield.total_lm());
    EXPECT_EQ(mesh_run.tally.emitted, mesh_run.tally.discarded + mesh_run.tally.direct +
                                          mesh_run.tally.farfield + mesh_run.tally.lost);
}

TEST(Mesh, BinaryAndAsciiStlAndScaledObjGiveTheSameSurface) {
    // Two triangles covering [-2, 2]^2 cm at z = -0.5 cm.
    const float tri[2][3][3] = {{{-2, -2, -0.5f}, {2, -2, -0.5f}, {2, 2, -0.5f}},
                                {{-2, -2, -0.5f}, {2, 2, -0.5f}, {-2, 2, -0.5f}}};
    std::string bin(80, ' ');
    const std::uint32_t count = 2;
    bin.append(reinterpret_cast<const char*>(&count), 4);
    for (const auto& t : tri) {
        bin.append(12, '\0');
        bin.append(reinterpret_cast<const char*>(t), 36);
        bin.append(2, '\0');
    }
    write(temp("sq.stl"), bin);
    std::string ascii = "solid sq\n";
    for (const auto& t : tri) {
        ascii += "facet normal 0 0 1\nouter loop\n";
        for (const auto& v : t)
            ascii += "vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                     std::to_string(v[2]) + "\n";
        ascii += "endloop\nendfacet\n";
    }
    write(temp("sq_ascii.stl"), ascii + "endsolid sq\n");
    write(temp("sq.obj"), "v -2 -2 -0.5\nv 2 -2 -0.5\nv 2 2 -0.5\nv -2 2 -0.5\nf 1 2 3 4\n");
    const Holder h{{-20, -20, -10}, {20, 20, 4}};
    for (const char* name : {"sq.stl", "sq_ascii.stl", "sq.obj"}) {
        const MeshHeightField field(load_mesh(temp(name), 10.0), h, name);
        EXPECT_NEAR(field.height(3.0, -7.0).value_or(1e9), -5.0, 1e-6) << name;
    }
}

struct BadMesh {
    std::string file;
    std::string contents;
    std::string expect;
};

class BadMeshes : public ::testing::TestWithParam<BadMesh> {};

TEST_P(BadMeshes, AreRefusedWithWhereAndWhy) {
    const BadMesh& b = GetParam();
    write(temp(b.file), b.contents);
    try {
        (void)parse_scene(mesh_scene(temp(b.file)), temp("bad_mesh.toml"));
        FAIL() << "accepted " << b.file;
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(b.expect), std::string::npos) << e.what();
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
}

std::string full_square(double z) {
    const std::string zs = std::to_string(z);
    return "v -20 -20 " + zs + "\nv 20 -20 " + zs + "\nv 20 20 " + zs + "\nv -20 20 " + zs + "\n";
}

INSTANTIATE_TEST_SUITE_P(
    Table, BadMeshes,
    ::testing::Values(
        BadMesh{"fold.obj",
                full_square(-2) +
                    "v -20 -20 -5\nv 20 20 -5\nv 20 -20 -5\nf 1 2 3\nf 1 3 4\nf 5 6 7\n",
                "a fold or an overhang"},
        BadMesh{"hole.obj", full_square(-2) + "f 1 2 3\n", "a hole"},
        BadMesh{"small.obj", "v -5 -5 -2\nv 5 -5 -2\nv 5 5 -2\nv -5 5 -2\nf 1 2 3 4\n",
                "does not cover"},
        BadMesh{"index2.obj", full_square(-2) + "f 1 2 9\n",
                ":5: face index 9 refers to no vertex"},
        BadMesh{"nan.stl",
                std::string(80, ' ') + std::string("\x01\0\0\0", 4) + std::string(12, '\0') +
                    std::string("\0\0\xc0\x7f", 4) + std::string(34, '\0'),
                "triangle 0: a vertex coordinate is not finite"},
        BadMesh{"word.obj", "v 0 0 zero\n", ":1: a vertex needs three numbers"},
        BadMesh{"short.obj", "v 0 0\n", ":1: a vertex needs three numbers"},
        BadMesh{"empty.obj", "# nothing\n", "no triangles"},
        BadMesh{"trunc.stl",
                std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(60, '\0'),
                "does not match its 5 triangles"},
        BadMesh{"facet.stl",
                "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n",
                ":6: a facet needs three vertices"},
        BadMesh{"mesh.ply", "ply\n", "unknown mesh format"}));

} // namespace
} // namespace fird
