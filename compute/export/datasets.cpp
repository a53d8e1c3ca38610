#include "datasets.hpp"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkFloatArray.h>
#include <vtkHexahedron.h>
#include <vtkImageData.h>
#include <vtkIntArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkStructuredGrid.h>
#include <vtkUnsignedIntArray.h>
#include <vtkUnstructuredGrid.h>

namespace fird::vtkio {

namespace {

constexpr double kPi = std::numbers::pi;

template <typename Array> vtkSmartPointer<Array> named(const char* name, int components = 1) {
    auto a = vtkSmartPointer<Array>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    return a;
}

void add_farfield_arrays(vtkCellData* cd, const FarField& f, const FarField* target,
                         bool image_rows_up) {
    const std::size_t n = f.lm.size();
    auto lumens = named<vtkFloatArray>("lumens");
    auto candela = named<vtkFloatArray>("candela");
    auto target_lm = named<vtkFloatArray>("target_lumens");
    auto difference = named<vtkFloatArray>("difference_lumens");
    for (auto* a : {lumens.Get(), candela.Get(), target_lm.Get(), difference.Get()})
        a->SetNumberOfTuples(vtkIdType(n));
    for (std::uint32_t r = 0; r < f.height; ++r)
        for (std::uint32_t c = 0; c < f.width; ++c) {
            // The image counts rows from the bottom (altitude -90); the far field from the
            // zenith.
            const std::uint32_t row = image_rows_up ? f.height - 1 - r : r;
            const vtkIdType id = vtkIdType(std::size_t(r) * f.width + c);
            const double v = f.lm[std::size_t(row) * f.width + c];
            lumens->SetValue(id, float(v));
            candela->SetValue(id, float(v / farfield_cell_solid_angle_sr(row, f.width, f.height)));
            if (target) {
                const double t = target->lm[std::size_t(row) * f.width + c];
                target_lm->SetValue(id, float(t));
                difference->SetValue(id, float(v - t));
            }
        }
    cd->AddArray(lumens);
    cd->AddArray(candela);
    if (target) {
        cd->AddArray(target_lm);
        cd->AddArray(difference);
    }
    cd->SetActiveScalars("lumens");
}

vtkSmartPointer<vtkStructuredGrid> grid(std::uint32_t w, std::uint32_t h,
                                        vtkSmartPointer<vtkPoints> points) {
    auto g = vtkSmartPointer<vtkStructuredGrid>::New();
    g->SetDimensions(int(w), int(h), 1);
    g->SetPoints(points);
    return g;
}

} // namespace


vtkSmartPointer<vtkStructuredGrid> reflector_grid(const Holder& hd, std::uint32_t w,
                                                  std::uint32_t h,
                                                  const std::vector<float>& heights,
                                                  const std::vector<glm::vec2>& gradients,
                                                  const TexelHits* hits) {
    const double dx = (hd.max_mm.x - hd.min_mm.x) / w, dy = (hd.max_mm.y - hd.min_mm.y) / h;
    auto points = vtkSmartPointer<vtkPoints>::New();
    points->SetNumberOfPoints(vtkIdType(w) * h);
    auto height = named<vtkFloatArray>("height_mm");
    auto normal = named<vtkFloatArray>("normal", 3);
    height->SetNumberOfTuples(vtkIdType(w) * h);
    normal->SetNumberOfTuples(vtkIdType(w) * h);
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const std::size_t t = std::size_t(j) * w + i;
            points->SetPoint(vtkIdType(t), hd.min_mm.x + (i + 0.5) * dx,
                             hd.min_mm.y + (j + 0.5) * dy, heights[t]);
            height->SetValue(vtkIdType(t), heights[t]);
            const glm::vec3 n = glm::normalize(glm::vec3(-gradients[t], 1.0f));
            normal->SetTuple3(vtkIdType(t), n.x, n.y, n.z);
        }
    auto g = grid(w, h, points);
    g->GetPointData()->AddArray(height);
    g->GetPointData()->SetNormals(normal);
    g->GetPointData()->SetActiveScalars("height_mm");
    if (hits) {
        // Per texel, hence per point: a point is a texel's centre.
        auto all = named<vtkUnsignedIntArray>("hits");
        auto first = named<vtkUnsignedIntArray>("first_hits");
        all->SetNumberOfTuples(vtkIdType(w) * h);
        first->SetNumberOfTuples(vtkIdType(w) * h);
        for (std::size_t t = 0; t < std::size_t(w) * h; ++t) {
            all->SetValue(vtkIdType(t), hits->all[t]);
            first->SetValue(vtkIdType(t), hits->first[t]);
        }
        g->GetPointData()->AddArray(all);
        g->GetPointData()->AddArray(first);
    }
    return g;
}

vtkSmartPointer<vtkStructuredGrid> surface_grid(const Surface& s, std::uint32_t w,
                                                std::uint32_t h) {
    const Holder& hd = s.holder();
    const double dx = (hd.max_mm.x - hd.min_mm.x) / w, dy = (hd.max_mm.y - hd.min_mm.y) / h;
    auto points = vtkSmartPointer<vtkPoints>::New();
    auto height = named<vtkFloatArray>("height_mm");
    for (std::uint32_t j = 0; j < h; ++j)
        for (std::uint32_t i = 0; i < w; ++i) {
            const double x = hd.min_mm.x + (i + 0.5) * dx, y = hd.min_mm.y + (j + 0.5) * dy;
            const double z = s.height(x, y);
            points->InsertNextPoint(x, y, z);
            height->InsertNextValue(float(z));
        }
    auto g = grid(w, h, points);
    g->GetPointData()->AddArray(height);
    g->GetPointData()->SetActiveScalars("height_mm");
    return g;
}

std::uint64_t quadtree_box_count(const QuadtreeLayout& q,
                                 const std::vector<std::uint32_t>& levels) {
    std::uint64_t n = 0;
    for (std::uint32_t l : levels)
        n += std::uint64_t(q.w[l]) * q.h[l];
    return n;
}

vtkSmartPointer<vtkUnstructuredGrid> quadtree_boxes(const Holder& hd, const QuadtreeLayout& q,
                                                    const std::vector<float>& tree,
                                                    const std::vector<std::uint32_t>& levels) {
    const double dx = (hd.max_mm.x - hd.min_mm.x) / q.w[0],
                 dy = (hd.max_mm.y - hd.min_mm.y) / q.h[0];
    auto points = vtkSmartPointer<vtkPoints>::New();
    auto u = vtkSmartPointer<vtkUnstructuredGrid>::New();
    auto level = named<vtkIntArray>("level");
    auto max_height = named<vtkFloatArray>("max_height_mm");
    u->Allocate(vtkIdType(quadtree_box_count(q, levels)));
    for (std::uint32_t l : levels) {
        const std::uint32_t span = 1u << l; // texels per node side (fewer at the far edges)
        for (std::uint32_t j = 0; j < q.h[l]; ++j)
            for (std::uint32_t i = 0; i < q.w[l]; ++i) {
                const double x0 = hd.min_mm.x + double(i * span) * dx;
                const double x1 = hd.min_mm.x + double(std::min((i + 1) * span, q.w[0])) * dx;
                const double y0 = hd.min_mm.y + double(j * span) * dy;
                const double y1 = hd.min_mm.y + double(std::min((j + 1) * span, q.h[0])) * dy;
                const float top = tree[q.offset[l] + std::size_t(j) * q.w[l] + i];
                const double z0 = hd.min_mm.z, z1 = std::max<double>(top, hd.min_mm.z);
                vtkIdType ids[8];
                const double corners[8][3] = {{x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0},
                                              {x0, y1, z0}, {x0, y0, z1}, {x1, y0, z1},
                                              {x1, y1, z1}, {x0, y1, z1}};
                for (int k = 0; k < 8; ++k)
                    ids[k] = points->InsertNextPoint(corners[k]);
                u->InsertNextCell(VTK_HEXAHEDRON, 8, ids);
                level->InsertNextValue(int(l));
                max_height->InsertNextValue(top);
            }
    }
    u->SetPoints(points);
    u->GetCellData()->AddArray(level);
    u->GetCellData()->AddArray(max_height);
    u->GetCellData()->SetActiveScalars("max_height_mm");
    return u;
}

vtkSmartPointer<vtkPolyData> ray_paths(const std::vector<RayPath>& paths, double energy_lm) {
    auto points = vtkSmartPointer<vtkPoints>::New();
    auto lines = vtkSmartPointer<vtkCellArray>::New();
    auto bounce = named<vtkIntArray>("bounce");
    auto bounces = named<vtkIntArray>("bounces");
    auto energy = named<vtkFloatArray>("energy_lm");
    for (const RayPath& p : paths) {
        lines->InsertNextCell(int(p.vertices.size()));
        for (std::size_t k = 0; k < p.vertices.size(); ++k) {
            const glm::dvec3& v = p.vertices[k];
            lines->InsertCellPoint(points->InsertNextPoint(v.x, v.y, v.z));
            // Reflections before this point: 0 at the source, k at the k-th hit, and the
            // exit point after the last.
            bounce->InsertNextValue(int(std::min<std::size_t>(k, p.reflections)));
        }
        bounces->InsertNextValue(int(p.reflections));
        energy->InsertNextValue(float(energy_lm));
    }
    auto d = vtkSmartPointer<vtkPolyData>::New();
    d->SetPoints(points);
    d->SetLines(lines);
    d->GetPointData()->AddArray(bounce);
    d->GetCellData()->AddArray(bounces);
    d->GetCellData()->AddArray(energy);
    return d;
}

vtkSmartPointer<vtkImageData> farfield_image(const FarField& f, const FarField* target) {
    auto img = vtkSmartPointer<vtkImageData>::New();
    // Cells are the far field's: points at the cell corners, in degrees.
    img->SetDimensions(int(f.width) + 1, int(f.height) + 1, 1);
    img->SetOrigin(-180.0, -90.0, 0.0);
    img->SetSpacing(360.0 / f.width, 180.0 / f.height, 1.0);
    add_farfield_arrays(img->GetCellData(), f, target, true);
    return img;
}

vtkSmartPointer<vtkPolyData> farfield_sphere(const FarField& f, const FarField* target) {
    auto points = vtkSmartPointer<vtkPoints>::New();
    for (std::uint32_t r = 0; r <= f.height; ++r)
        for (std::uint32_t c = 0; c <= f.width; ++c) {
            const double theta = kPi / 2 - kPi * r / f.height, phi = -kPi + 2 * kPi * c / f.width;
            points->InsertNextPoint(std::cos(theta) * std::cos(phi),
                                    std::cos(theta) * std::sin(phi), std::sin(theta));
        }
    auto quads = vtkSmartPointer<vtkCellArray>::New();
    auto solid = named<vtkFloatArray>("solid_angle_sr");
    const auto id = [&](std::uint32_t r, std::uint32_t c) {
        return vtkIdType(std::size_t(r) * (f.width + 1) + c);
    };
    for (std::uint32_t r = 0; r < f.height; ++r)
        for (std::uint32_t c = 0; c < f.width; ++c) {
            const vtkIdType q[4] = {id(r, c), id(r + 1, c), id(r + 1, c + 1), id(r, c + 1)};
            quads->InsertNextCell(4, q);
            solid->InsertNextValue(float(farfield_cell_solid_angle_sr(r, f.width, f.height)));
        }
    auto d = vtkSmartPointer<vtkPolyData>::New();
    d->SetPoints(points);
    d->SetPolys(quads);
    add_farfield_arrays(d->GetCellData(), f, target, false);
    d->GetCellData()->AddArray(solid);
    return d;
}

vtkSmartPointer<vtkPolyData> source_surface(const SourceDesc& s) {
    auto points = vtkSmartPointer<vtkPoints>::New();
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    auto d = vtkSmartPointer<vtkPolyData>::New();
    constexpr int kAround = 48, kRings = 24;
    if (s.kind == SourceKind::Point) {
        const vtkIdType p = points->InsertNextPoint(s.center_mm.x, s.center_mm.y, s.center_mm.z);
        cells->InsertNextCell(1, &p);
        d->SetPoints(points);
        d->SetVerts(cells);
        return d;
    }
    if (s.kind == SourceKind::Cylinder) {
        // The lateral surface (the caps are dark): rings at both ends.
        const glm::dvec3 a = glm::normalize(s.axis);
        const glm::dvec3 u = glm::normalize(
            glm::cross(a, std::abs(a.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
        const glm::dvec3 v = glm::cross(a, u);
        for (int end = 0; end < 2; ++end)
            for (int k = 0; k < kAround; ++k) {
                const double t = 2 * kPi * k / kAround;
                const glm::dvec3 p = s.center_mm + (end - 0.5) * s.length_mm * a +
                                     s.radius_mm * (std::cos(t) * u + std::sin(t) * v);
                points->InsertNextPoint(p.x, p.y, p.z);
            }
        for (int k = 0; k < kAround; ++k) {
            const vtkIdType q[4] = {k, (k + 1) % kAround, kAround + (k + 1) % kAround, kAround + k};
            cells->InsertNextCell(4, q);
        }
    } else {
        for (int r = 0; r <= kRings; ++r)
            for (int k = 0; k < kAround; ++k) {
                const double theta = kPi * r / kRings, phi = 2 * kPi * k / kAround;
                points->InsertNextPoint(
                    s.center_mm.x + s.radius_mm * std::sin(theta) * std::cos(phi),
                    s.center_mm.y + s.radius_mm * std::sin(theta) * std::sin(phi),
                    s.center_mm.z + s.radius_mm * std::cos(theta));
            }
        for (int r = 0; r < kRings; ++r)
            for (int k = 0; k < kAround; ++k) {
                const vtkIdType q[4] = {r * kAround + k, r * kAround + (k + 1) % kAround,
                                        (r + 1) * kAround + (k + 1) % kAround,
                                        (r + 1) * kAround + k};
                cells->InsertNextCell(4, q);
            }
    }
    d->SetPoints(points);
    d->SetPolys(cells);
    return d;
}

vtkSmartPointer<vtkPolyData> holder_box(const Holder& h) {
    auto points = vtkSmartPointer<vtkPoints>::New();
    for (int k = 0; k < 8; ++k)
        points->InsertNextPoint(k & 1 ? h.max_mm.x : h.min_mm.x, k & 2 ? h.max_mm.y : h.min_mm.y,
                                k & 4 ? h.max_mm.z : h.min_mm.z);
    auto cells = vtkSmartPointer<vtkCellArray>::New();
    const vtkIdType faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces)
        cells->InsertNextCell(4, f);
    auto d = vtkSmartPointer<vtkPolyData>::New();
    d->SetPoints(points);
    d->SetPolys(cells);
    return d;
}

} // namespace fird::vtkio
