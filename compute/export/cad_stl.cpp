#include "cad_stl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Poly_Triangulation.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include "io/atomic_file.hpp"

namespace fird {

namespace {

using Triangle = StlTriangle;

void put_float(std::string& out, double v) {
    const float f = float(v);
    char b[4];
    std::memcpy(b, &f, 4);
    out.append(b, 4);
}

// The reflector's triangles, each wound counter-clockwise seen from outside.
std::vector<Triangle> triangles(const SurfaceGrid& g, double thickness_mm) {
    const auto top = [&](int i, int j) { return g.points[std::size_t(j) * g.nx + i]; };
    const auto back = [&](int i, int j) {
        const std::size_t k = std::size_t(j) * g.nx + i;
        return g.points[k] - thickness_mm * g.normals[k];
    };
    std::vector<Triangle> t;
    for (int j = 0; j + 1 < g.ny; ++j)
        for (int i = 0; i + 1 < g.nx; ++i) {
            t.push_back({top(i, j), top(i + 1, j), top(i + 1, j + 1)});
            t.push_back({top(i, j), top(i + 1, j + 1), top(i, j + 1)});
            if (thickness_mm > 0.0) { // the same cells, wound the other way: facing down
                t.push_back({back(i, j), back(i + 1, j + 1), back(i + 1, j)});
                t.push_back({back(i, j), back(i, j + 1), back(i + 1, j + 1)});
            }
        }
    if (thickness_mm <= 0.0) return t;
    // The rim, counter-clockwise seen from above (the part on the left of each step):
    // for a step a -> b the wall's outward side is on the right.
    std::vector<std::array<int, 2>> rim;
    for (int i = 0; i + 1 < g.nx; ++i)
        rim.push_back({i, 0});
    for (int j = 0; j + 1 < g.ny; ++j)
        rim.push_back({g.nx - 1, j});
    for (int i = g.nx - 1; i > 0; --i)
        rim.push_back({i, g.ny - 1});
    for (int j = g.ny - 1; j > 0; --j)
        rim.push_back({0, j});
    for (std::size_t k = 0; k < rim.size(); ++k) {
        const auto [ai, aj] = rim[k];
        const auto [bi, bj] = rim[(k + 1) % rim.size()];
        t.push_back({top(ai, aj), back(bi, bj), top(bi, bj)});
        t.push_back({top(ai, aj), back(ai, aj), back(bi, bj)});
    }
    return t;
}

} // namespace

SurfaceGrid sample_surface(const Handle(Geom_BSplineSurface) & s, int nx, int ny) {
    double u0, u1, v0, v1;
    s->Bounds(u0, u1, v0, v1);
    SurfaceGrid g{nx, ny, {}, {}};
    g.points.reserve(std::size_t(nx) * ny);
    g.normals.reserve(std::size_t(nx) * ny);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            // The rims exactly on the parameter bounds, so the sides are planar walls.
            const double u = i + 1 == nx ? u1 : u0 + (u1 - u0) * i / (nx - 1);
            const double v = j + 1 == ny ? v1 : v0 + (v1 - v0) * j / (ny - 1);
            gp_Pnt p;
            gp_Vec du, dv;
            s->D1(u, v, p, du, dv);
            const gp_Vec n = du.Crossed(dv);
            g.points.push_back({p.X(), p.Y(), p.Z()});
            g.normals.push_back(glm::normalize(glm::dvec3{n.X(), n.Y(), n.Z()}));
        }
    return g;
}

SurfaceGrid sample_family(const Surface& surface, int nx, int ny) {
    const Holder& h = surface.holder();
    SurfaceGrid g{nx, ny, {}, {}};
    g.points.reserve(std::size_t(nx) * ny);
    g.normals.reserve(std::size_t(nx) * ny);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            // The rims exactly on the holder's, so the sides are planar walls.
            const double x =
                i + 1 == nx ? h.max_mm.x : h.min_mm.x + (h.max_mm.x - h.min_mm.x) * i / (nx - 1);
            const double y =
                j + 1 == ny ? h.max_mm.y : h.min_mm.y + (h.max_mm.y - h.min_mm.y) * j / (ny - 1);
            const glm::dvec2 grad = surface.raw_gradient(x, y);
            g.points.push_back({x, y, surface.raw(x, y)});
            g.normals.push_back(glm::normalize(glm::dvec3{-grad.x, -grad.y, 1.0}));
        }
    return g;
}

double chord_error_mm(const SurfaceGrid& g,
                      const std::function<double(double, double)>& height_mm) {
    double worst = 0.0;
    const auto gap = [&](const glm::dvec3& q) {
        worst = std::max(worst, std::abs(height_mm(q.x, q.y) - q.z));
    };
    for (const Triangle& t : triangles(g, 0.0)) {
        gap((t[0] + t[1] + t[2]) / 3.0);
        gap(0.5 * (t[0] + t[1]));
        gap(0.5 * (t[1] + t[2]));
        gap(0.5 * (t[2] + t[0]));
    }
    return worst;
}

std::uint64_t write_stl(const std::vector<StlTriangle>& tris, const std::string& header,
                        const std::string& path) {
    std::string out(80, '\0');
    std::copy(header.begin(),
              header.begin() + std::ptrdiff_t(std::min<std::size_t>(80, header.size())),
              out.begin());
    const auto count = std::uint32_t(tris.size());
    out.append(reinterpret_cast<const char*>(&count), 4);
    out.reserve(84 + 50 * tris.size());
    for (const Triangle& t : tris) {
        const glm::dvec3 c = glm::cross(t[1] - t[0], t[2] - t[0]);
        const double len = glm::length(c);
        const glm::dvec3 n = len > 0.0 ? c / len : glm::dvec3(0.0);
        for (int k = 0; k < 3; ++k)
            put_float(out, n[k]);
        for (const glm::dvec3& p : t)
            for (int k = 0; k < 3; ++k)
                put_float(out, p[k]);
        out.append(2, '\0');
    }
    write_atomically(path, [&](const std::string& temporary) {
        std::ofstream f(temporary, std::ios::binary);
        if (!f) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
        f.write(out.data(), std::streamsize(out.size()));
        f.close();
        if (!f) throw std::runtime_error(fmt::format("{}: write failed", path));
    });
    return out.size();
}

std::uint64_t write_reflector_stl(const SurfaceGrid& g, double thickness_mm,
                                  const std::string& path) {
    return write_stl(triangles(g, thickness_mm),
                     thickness_mm > 0.0
                         ? fmt::format("fird reflector, sheet {:g} mm, mm", thickness_mm)
                         : std::string("fird reflector surface, mm"),
                     path);
}

std::vector<StlTriangle> tessellate(const TopoDS_Shape& shape, double deflection_mm) {
    BRepMesh_IncrementalMesh mesh(shape, deflection_mm, Standard_False, 0.5);
    if (!mesh.IsDone()) throw std::runtime_error("OpenCASCADE could not mesh the reflector");
    // Each face's triangles, wound by the face's orientation. Those with two corners at one
    // point go: a revolved face's pole (a degenerate edge) gets a fan of them, which would
    // leave facets with no normal and edges of no length.
    std::vector<StlTriangle> tris;
    for (TopExp_Explorer e(shape, TopAbs_FACE); e.More(); e.Next()) {
        const TopoDS_Face face = TopoDS::Face(e.Current());
        TopLoc_Location where;
        const Handle(Poly_Triangulation) t = BRep_Tool::Triangulation(face, where);
        // A face left unmeshed would be a hole in the STL.
        if (t.IsNull())
            throw std::runtime_error("OpenCASCADE left a face of the reflector unmeshed");
        const bool reversed = face.Orientation() == TopAbs_REVERSED;
        const auto node = [&](int k) {
            const gp_Pnt p = t->Node(k).Transformed(where.Transformation());
            return glm::dvec3(p.X(), p.Y(), p.Z());
        };
        for (int k = 1; k <= t->NbTriangles(); ++k) {
            int a, b, c;
            t->Triangle(k).Get(a, b, c);
            if (reversed) std::swap(b, c);
            const StlTriangle tri{node(a), node(b), node(c)};
            if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
            tris.push_back(tri);
        }
    }
    return tris;
}

} // namespace fird
