// fird export's files read back with VTK's own XML readers and checked against what the
// engine computed: heights and normals against the analytic family, hits against the
// reflections, the quadtree's max-mip property, ray paths against the CPU reference,
// the far field's total, the sphere's area, and the collection's entries.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <regex>
#include <sstream>

#include <glm/geometric.hpp>
#include <vtkCell.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkStructuredGrid.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLStructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "export/scene_export.hpp"
#include "io/scene_file.hpp"
#include "reference/reference_tracer.hpp"
#include "scratch_dir.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

namespace fs = std::filesystem;

template <typename Reader> auto read(const std::string& path) {
    auto r = vtkSmartPointer<Reader>::New();
    r->SetFileName(path.c_str());
    r->Update();
    EXPECT_EQ(r->GetErrorCode(), 0u) << path;
    return vtkSmartPointer<std::remove_pointer_t<decltype(r->GetOutput())>>(r->GetOutput());
}

// Model B at a small height field and ray count: five bounces, a steep cup.
Scene model_b() {
    Scene s = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/model_b.toml");
    s.trace.heightfield_w = 300;
    s.trace.heightfield_h = 200;
    s.trace.rays = 200000;
    return s;
}

// Ray paths exported: enough that the 97 % bound below sits 3 sigma under the share of
// hits within a tenth of a texel (98.3 % over 3000 paths, independent or stratified rays).
constexpr std::uint32_t kPaths = 1000;

const ScratchDir& kScratch = add_scratch_dir("fird_export");

class Export : public VulkanTest {
  protected:
    static void SetUpTestSuite() {
        VulkanTest::SetUpTestSuite();
        dir_ = kScratch.fresh("model_b");
        report_ = export_scene(ctx(), model_b(), {.paths = kPaths}, dir_);
    }
    static std::string file(const char* name) { return (fs::path(dir_) / name).string(); }
    static std::string dir_;
    static ExportReport report_;
};
std::string Export::dir_;
ExportReport Export::report_;

TEST_F(Export, ReflectorGridHasTheFamilysHeightsNormalsAndEveryReflection) {
    const Scene s = model_b();
    const Surface surface = Surface::make(
        target_reflector(s).family == s.reflector.family ? s.reflector : s.reflector, s.holder);
    const auto g = read<vtkXMLStructuredGridReader>(file("reflector.vts"));
    int dims[3];
    g->GetDimensions(dims);
    EXPECT_EQ(dims[0], 300);
    EXPECT_EQ(dims[1], 200);
    EXPECT_EQ(dims[2], 1);
    vtkDataArray* normals = g->GetPointData()->GetArray("normal");
    ASSERT_TRUE(normals && g->GetPointData()->GetArray("height_mm"));
    for (vtkIdType id = 0; id < g->GetNumberOfPoints(); id += 997) {
        double p[3];
        g->GetPoint(id, p);
        EXPECT_NEAR(p[2], surface.height(p[0], p[1]), 1e-4) << id;
        const glm::dvec2 grad = surface.gradient(p[0], p[1]);
        const glm::dvec3 n = glm::normalize(glm::dvec3(-grad, 1.0));
        double m[3];
        normals->GetTuple(id, m);
        EXPECT_NEAR(glm::dot(n, glm::dvec3(m[0], m[1], m[2])), 1.0, 1e-4) << id;
    }
    // Hits: every reflection of the run, and the first ones one per reflected ray.
    vtkDataArray* hits = g->GetPointData()->GetArray("hits");
    vtkDataArray* first = g->GetPointData()->GetArray("first_hits");
    ASSERT_TRUE(hits && first);
    double all = 0.0, firsts = 0.0;
    for (vtkIdType id = 0; id < g->GetNumberOfPoints(); ++id) {
        all += hits->GetTuple1(id);
        firsts += first->GetTuple1(id);
    }
    double reflections = 0.0;
    const auto& by = report_.tally.by_reflections;
    for (std::size_t r = 0; r < by.size(); ++r)
        reflections += double(r) * double(by[r]);
    EXPECT_EQ(firsts, double(report_.tally.farfield)); // paper policy: all of them leave
    EXPECT_EQ(all, reflections);
    EXPECT_GT(all, firsts); // a cup: many rays reflect more than once
}

TEST_F(Export, QuadtreeNodesHoldTheMaximumOfTheirChildren) {
    const auto u = read<vtkXMLUnstructuredGridReader>(file("quadtree.vtu"));
    vtkDataArray* level = u->GetCellData()->GetArray("level");
    vtkDataArray* top = u->GetCellData()->GetArray("max_height_mm");
    ASSERT_TRUE(level && top);
    const Scene s = model_b();
    const double dx = (s.holder.max_mm.x - s.holder.min_mm.x) / 300;
    const double dy = (s.holder.max_mm.y - s.holder.min_mm.y) / 200;
    // Node (level, i, j) from its box's lower corner.
    std::map<std::tuple<int, int, int>, double> nodes;
    for (vtkIdType c = 0; c < u->GetNumberOfCells(); ++c) {
        const double* b = u->GetCell(c)->GetBounds();
        const int l = int(level->GetTuple1(c));
        const int i = int(std::lround((b[0] - s.holder.min_mm.x) / dx)) >> l;
        const int j = int(std::lround((b[2] - s.holder.min_mm.y) / dy)) >> l;
        nodes[{l, i, j}] = top->GetTuple1(c);
    }
    ASSERT_EQ(report_.quadtree_levels, 10u); // 300 x 200: all ten levels, under a million
    std::size_t checked = 0;
    for (const auto& [key, value] : nodes) {
        const auto [l, i, j] = key;
        if (l == 0) continue;
        double most = -1e30;
        for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di)
                if (const auto it = nodes.find({l - 1, 2 * i + di, 2 * j + dj}); it != nodes.end())
                    most = std::max(most, it->second);
        EXPECT_EQ(value, most) << l << " " << i << " " << j;
        ++checked;
    }
    EXPECT_GT(checked, 20000u);
}

TEST_F(Export, RayPathsFollowTheReferenceTracer) {
    const Scene s = model_b();
    const Surface surface = Surface::make(s.reflector, s.holder);
    const auto rays = sample_effective_rays(s, kPaths);
    const auto d = read<vtkXMLPolyDataReader>(file("rays.vtp"));
    ASSERT_EQ(d->GetNumberOfCells(), vtkIdType(rays.size()));
    vtkDataArray* bounces = d->GetCellData()->GetArray("bounces");
    ASSERT_TRUE(bounces && d->GetCellData()->GetArray("energy_lm") &&
                d->GetPointData()->GetArray("bounce"));
    const double texel = 10.0 / 300.0;
    std::size_t same = 0, vertices = 0, close = 0;
    for (vtkIdType c = 0; c < d->GetNumberOfCells(); ++c) {
        std::vector<glm::dvec3> ref;
        const PathResult r = trace_path(surface, s.holder, rays[std::size_t(c)],
                                        s.trace.max_bounces, s.trace.bounce_policy, &ref);
        vtkCell* cell = d->GetCell(c);
        const auto n = std::size_t(cell->GetNumberOfPoints());
        if (int(bounces->GetTuple1(c)) != int(r.reflections) || n != ref.size()) continue;
        ++same;
        // The hits (between the origin and the exit point).
        for (std::size_t k = 1; k + 1 < n; ++k) {
            double p[3];
            d->GetPoint(cell->GetPointId(int(k)), p);
            ++vertices;
            close += glm::length(glm::dvec3(p[0], p[1], p[2]) - ref[k]) < 0.1 * texel;
        }
    }
    // Rays grazing a wall may bounce once more or less on either side of float rounding.
    EXPECT_GE(same, std::size_t(0.97 * double(rays.size())));
    EXPECT_GE(close, std::size_t(0.97 * double(vertices)));
    EXPECT_GT(vertices, rays.size() / 2);
}

TEST_F(Export, FarFieldImageHoldsTheFarFieldFluxAndTheSphereIsWhole) {
    const auto img = read<vtkXMLImageDataReader>(file("farfield.vti"));
    vtkDataArray* lm = img->GetCellData()->GetArray("lumens");
    ASSERT_TRUE(lm && img->GetCellData()->GetArray("candela") &&
                img->GetCellData()->GetArray("target_lumens") &&
                img->GetCellData()->GetArray("difference_lumens"));
    EXPECT_EQ(img->GetNumberOfCells(), 1800 * 900);
    double total = 0.0;
    for (vtkIdType c = 0; c < lm->GetNumberOfTuples(); ++c)
        total += lm->GetTuple1(c);
    const double farfield_lm = double(report_.tally.farfield) * report_.energy_per_ray_lm;
    EXPECT_NEAR(total, farfield_lm, 1e-4 * farfield_lm);

    const auto sphere = read<vtkXMLPolyDataReader>(file("farfield_sphere.vtp"));
    ASSERT_EQ(sphere->GetNumberOfCells(), 1800 * 900);
    vtkDataArray* solid = sphere->GetCellData()->GetArray("solid_angle_sr");
    double area = 0.0, sr = 0.0;
    for (vtkIdType c = 0; c < sphere->GetNumberOfCells(); ++c) {
        vtkCell* q = sphere->GetCell(c);
        double p[4][3];
        for (int k = 0; k < 4; ++k)
            sphere->GetPoint(q->GetPointId(k), p[k]);
        const auto v = [&](int k) { return glm::dvec3(p[k][0], p[k][1], p[k][2]); };
        area += 0.5 * glm::length(glm::cross(v(1) - v(0), v(2) - v(0))) +
                0.5 * glm::length(glm::cross(v(2) - v(0), v(3) - v(0)));
        sr += solid->GetTuple1(c);
    }
    EXPECT_NEAR(area, 4.0 * std::numbers::pi, 1e-4);
    EXPECT_NEAR(sr, 4.0 * std::numbers::pi, 1e-4);
}

TEST_F(Export, TheCollectionListsOnlyFilesThatExist) {
    std::ifstream in(file("scene.pvd"));
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string xml = ss.str();
    const std::regex entry("file=\"([^\"]+)\"");
    std::size_t n = 0;
    for (std::sregex_iterator it(xml.begin(), xml.end(), entry), end; it != end; ++it, ++n)
        EXPECT_TRUE(fs::is_regular_file(fs::path(dir_) / (*it)[1].str())) << (*it)[1];
    EXPECT_EQ(n, 6u);
    for (const auto& f : report_.files)
        EXPECT_EQ(f.bytes, fs::file_size(fs::path(dir_) / f.name)) << f.name;
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos); // none left
}

using ExportLimits = VulkanTest;

TEST_F(ExportLimits, AQuadtreeRequestPastTheLimitIsClampedWithANote) {
    Scene s = model_b();
    s.trace.heightfield_w = s.trace.heightfield_h = 2400;
    s.trace.rays = 2000;
    const auto dir = kScratch.fresh("big");
    const ExportReport r = export_scene(ctx(), s, {.paths = 10, .levels = 13}, dir);
    ASSERT_EQ(r.notes.size(), 1u);
    EXPECT_NE(r.notes[0].find("--levels 13"), std::string::npos) << r.notes[0];
    EXPECT_LT(r.quadtree_levels, 13u);
    const auto u = read<vtkXMLUnstructuredGridReader>((fs::path(dir) / "quadtree.vtu").string());
    EXPECT_LE(u->GetNumberOfCells(), vtkIdType(kMaxQuadtreeBoxes));
    EXPECT_THROW(export_scene(ctx(), s, {.parameters = {{"nope", 1.0}}}, dir),
                 std::invalid_argument);
    EXPECT_THROW(export_scene(ctx(), s, {.levels = 40}, dir), std::invalid_argument);
}

} // namespace
} // namespace fird::test
