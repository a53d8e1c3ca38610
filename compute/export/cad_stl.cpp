#include "cad_stl.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <BRepMesh_IncrementalMesh.hxx>
#include <StlAPI_Writer.hxx>
#include <fmt/format.h>
#include <glm/geometric.hpp>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include "io/atomic_file.hpp"

namespace fird {

namespace {

using Triangle = std::array<glm::dvec3, 3>;

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

double chord_error_mm(const SurfaceGrid& g, const Handle(Geom_BSplineSurface) & s) {
    double worst = 0.0;
    const auto gap = [&](const glm::dvec3& q) {
        // S(u, v) = (u, v, z): the surface point over q is at parameters (q.x, q.y).
        worst = std::max(worst, std::abs(s->Value(q.x, q.y).Z() - q.z));
    };
    for (const Triangle& t : triangles(g, 0.0)) {
        gap((t[0] + t[1] + t[2]) / 3.0);
        gap(0.5 * (t[0] + t[1]));
        gap(0.5 * (t[1] + t[2]));
        gap(0.5 * (t[2] + t[0]));
    }
    return worst;
}

std::uint64_t write_reflector_stl(const SurfaceGrid& g, double thickness_mm,
                                  const std::string& path) {
    const std::vector<Triangle> tris = triangles(g, thickness_mm);
    std::string out(80, '\0');
    const std::string header = thickness_mm > 0.0
                                   ? fmt::format("fird reflector, sheet {:g} mm, mm", thickness_mm)
                                   : std::string("fird reflector surface, mm");
    std::copy(header.begin(), header.end(), out.begin());
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

std::uint64_t write_tessellated_stl(const TopoDS_Shape& shape, double deflection_mm,
                                    const std::string& path) {
    BRepMesh_IncrementalMesh mesh(shape, deflection_mm, Standard_False, 0.5);
    if (!mesh.IsDone())
        throw std::runtime_error(fmt::format("{}: OpenCASCADE could not mesh the "
                                             "reflector",
                                             path));
    StlAPI_Writer writer;
    writer.ASCIIMode() = Standard_False;
    write_atomically(path, [&](const std::string& temporary) {
        if (!writer.Write(shape, temporary.c_str()))
            throw std::runtime_error(fmt::format("{}: cannot write", path));
    });
    return std::filesystem::file_size(path);
}

} // namespace fird
