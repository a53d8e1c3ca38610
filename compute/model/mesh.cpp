#include "mesh.hpp"

#include <filesystem>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

namespace fird {

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) {
    throw std::runtime_error(where + ": " + what);
}

glm::dvec3 finite_vertex(const std::string& where, double x, double y, double z, double unit) {
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        fail(where, "a vertex coordinate is not finite");
    return {x * unit, y * unit, z * unit};
}

TriangleMesh load_obj(const std::string& path, std::istream& in, double unit) {
    TriangleMesh m;
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
        const std::string where = fmt::format("{}:{}", path, line_no);
        std::istringstream ls(line);
        std::string tag;
        if (!(ls >> tag) || tag[0] == '#') continue;
        if (tag == "v") {
            double x, y, z;
            if (!(ls >> x >> y >> z)) fail(where, "a vertex needs three numbers");
            m.vertices.push_back(finite_vertex(where, x, y, z, unit));
        } else if (tag == "f") {
            std::vector<std::uint32_t> face;
            std::string token;
            while (ls >> token) {
                long index = 0;
                try {
                    index = std::stol(token.substr(0, token.find('/')));
                } catch (const std::exception&) {
                    fail(where, fmt::format("bad face index '{}'", token));
                }
                const long n = long(m.vertices.size());
                const long resolved = index < 0 ? n + index : index - 1;
                if (index == 0 || resolved < 0 || resolved >= n)
                    fail(where,
                         fmt::format("face index {} refers to no vertex ({} so far)", index, n));
                face.push_back(std::uint32_t(resolved));
            }
            if (face.size() < 3) fail(where, "a face needs at least three vertices");
            for (std::size_t k = 1; k + 1 < face.size(); ++k)
                m.triangles.push_back({face[0], face[k], face[k + 1]});
        }
        // vt, vn, g, o, s, usemtl, mtllib: not needed for the geometry.
    }
    return m;
}

TriangleMesh load_stl(const std::string& path, const std::string& bytes, double unit) {
    TriangleMesh m;
    const auto add = [&](const std::string& where, const glm::dvec3 v[3]) {
        const auto base = std::uint32_t(m.vertices.size());
        for (int k = 0; k < 3; ++k)
            m.vertices.push_back(finite_vertex(where, v[k].x, v[k].y, v[k].z, unit));
        m.triangles.push_back({base, base + 1, base + 2});
    };
    std::uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    const bool binary = bytes.size() >= 84 && bytes.size() == 84 + std::uint64_t(count) * 50;
    if (binary) {
        for (std::uint32_t t = 0; t < count; ++t) {
            const char* rec = bytes.data() + 84 + std::size_t(t) * 50 + 12; // skip the normal
            glm::dvec3 v[3];
            for (int k = 0; k < 3; ++k) {
                float xyz[3];
                std::memcpy(xyz, rec + k * 12, 12);
                v[k] = {xyz[0], xyz[1], xyz[2]};
            }
            add(fmt::format("{}: triangle {}", path, t), v);
        }
        return m;
    }
    if (bytes.rfind("solid", 0) != 0)
        fail(path,
             fmt::format("not an STL file: binary size {} does not match its {} triangles, and "
                         "it does not start with 'solid'",
                         bytes.size(), count));
    std::istringstream in(bytes);
    std::string line;
    glm::dvec3 v[3];
    int have = 0;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
        const std::string where = fmt::format("{}:{}", path, line_no);
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "vertex") {
            double x, y, z;
            if (!(ls >> x >> y >> z)) fail(where, "a vertex needs three numbers");
            if (have == 3) fail(where, "more than three vertices in a facet");
            v[have++] = {x, y, z};
        } else if (tag == "endloop") {
            if (have != 3) fail(where, "a facet needs three vertices");
            add(where, v);
            have = 0;
        }
    }
    if (have != 0) fail(path, "truncated: the last facet is incomplete");
    return m;
}

double cross2(glm::dvec2 a, glm::dvec2 b) {
    return a.x * b.y - a.y * b.x;
}

} // namespace

TriangleMesh load_mesh(const std::string& path, double unit_mm) {
    if (std::filesystem::is_directory(path))
        throw std::runtime_error(path + ": is a directory, not a mesh file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open the mesh file");
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return parse_mesh(path, bytes, unit_mm);
}

TriangleMesh parse_mesh(const std::string& path, const std::string& bytes, double unit_mm) {
    std::string lower = path;
    std::transform(lower.begin(), lower.end(), lower.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    TriangleMesh m;
    if (lower.size() >= 4 && lower.substr(lower.size() - 4) == ".obj") {
        std::istringstream s(bytes);
        m = load_obj(path, s, unit_mm);
    } else if (lower.size() >= 4 && lower.substr(lower.size() - 4) == ".stl") {
        m = load_stl(path, bytes, unit_mm);
    } else {
        fail(path, "unknown mesh format (use .obj or .stl)");
    }
    if (m.triangles.empty()) fail(path, "the mesh has no triangles");
    return m;
}

MeshHeightField::MeshHeightField(TriangleMesh mesh, const Holder& holder, const std::string& name)
    : mesh_(std::move(mesh)), holder_(holder) {
    const double w = holder.max_mm.x - holder.min_mm.x;
    const double h = holder.max_mm.y - holder.min_mm.y;
    const double cells = std::clamp(double(mesh_.triangles.size()) / 2.0, 1.0, 4.0e6);
    nx_ = std::max(1, int(std::sqrt(cells * w / h)));
    ny_ = std::max(1, int(cells / nx_));
    cells_.assign(std::size_t(nx_) * ny_, {});
    cell_z_.assign(cells_.size(), {1e300, -1e300});
    planes_.resize(mesh_.triangles.size());
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
        const auto& tri = mesh_.triangles[t];
        const glm::dvec3 &a = mesh_.vertices[tri[0]], &b = mesh_.vertices[tri[1]],
                         &c = mesh_.vertices[tri[2]];
        // Vertical (zero projected area) triangles are cliffs: not needed to locate points.
        if (std::abs(cross2(glm::dvec2(b - a), glm::dvec2(c - a))) < 1e-12) continue;
        const glm::dvec3 n = glm::dvec3((b.y - a.y) * (c.z - a.z) - (b.z - a.z) * (c.y - a.y),
                                        (b.z - a.z) * (c.x - a.x) - (b.x - a.x) * (c.z - a.z),
                                        (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        const double gx = -n.x / n.z, gy = -n.y / n.z;
        planes_[t] = {a.z - gx * a.x - gy * a.y,
                      gx,
                      gy,
                      std::min({a.x, b.x, c.x}),
                      std::max({a.x, b.x, c.x}),
                      std::min({a.y, b.y, c.y}),
                      std::max({a.y, b.y, c.y})};
        const auto [i0, j0] = cell_of(std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}));
        const auto [i1, j1] = cell_of(std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}));
        const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const std::size_t k = std::size_t(j) * nx_ + i;
                cells_[k].push_back(t);
                cell_z_[k].first = std::min(cell_z_[k].first, zlo);
                cell_z_[k].second = std::max(cell_z_[k].second, zhi);
            }
    }
    // The graph check: every sample of a fine grid over the holder rectangle lies over
    // exactly one triangle (strictly inside: shared edges are not overlaps).
    constexpr int kSamples = 400;
    for (int j = 0; j < kSamples; ++j)
        for (int i = 0; i < kSamples; ++i) {
            const double x = holder.min_mm.x + (i + 0.5) / kSamples * w;
            const double y = holder.min_mm.y + (j + 0.5) / kSamples * h;
            int covering = 0;
            std::uint32_t first = 0;
            const auto [ci, cj] = cell_of(x, y);
            for (std::uint32_t t : cells_[std::size_t(cj) * nx_ + ci]) {
                const auto& tri = mesh_.triangles[t];
                const glm::dvec2 p(x, y), a(mesh_.vertices[tri[0]]), b(mesh_.vertices[tri[1]]),
                    c(mesh_.vertices[tri[2]]);
                const double area = cross2(b - a, c - a);
                const double u = cross2(b - p, c - p) / area, v = cross2(c - p, a - p) / area;
                const double eps = 1e-9;
                if (u > eps && v > eps && 1.0 - u - v > eps) {
                    if (covering++ == 0)
                        first = t;
                    else
                        throw std::invalid_argument(fmt::format(
                            "{}: not a height field: triangles {} and {} both lie over (x, y) = "
                            "({:.3f}, {:.3f}) mm (a fold or an overhang)",
                            name, first, t, x, y));
                }
            }
            if (covering == 0) {
                // On an edge or vertex is fine; a real hole is not covered within a tolerance.
                if (!height(x, y))
                    throw std::invalid_argument(fmt::format(
                        "{}: not a height field over the holder: no triangle over (x, y) = "
                        "({:.3f}, {:.3f}) mm (a hole, or the mesh does not cover the footprint)",
                        name, x, y));
            }
        }
}

std::pair<int, int> MeshHeightField::cell_of(double x, double y) const {
    const double fx = (x - holder_.min_mm.x) / (holder_.max_mm.x - holder_.min_mm.x);
    const double fy = (y - holder_.min_mm.y) / (holder_.max_mm.y - holder_.min_mm.y);
    // Clamped as doubles: a far vertex (1e110 mm) must not overflow the int.
    const auto index = [](double f, int n) {
        const double i = std::floor(f * n);
        return i >= 0.0 ? int(std::min(i, double(n - 1))) : 0;
    };
    return {index(fx, nx_), index(fy, ny_)};
}

std::optional<double> MeshHeightField::height(double x, double y, glm::dvec2* gradient) const {
    const auto [ci, cj] = cell_of(x, y);
    for (std::uint32_t t : cells_[std::size_t(cj) * nx_ + ci]) {
        const auto& tri = mesh_.triangles[t];
        const glm::dvec3 &A = mesh_.vertices[tri[0]], &B = mesh_.vertices[tri[1]],
                         &C = mesh_.vertices[tri[2]];
        const glm::dvec2 p(x, y), a(A), b(B), c(C);
        const double area = cross2(b - a, c - a);
        const double u = cross2(b - p, c - p) / area, v = cross2(c - p, a - p) / area,
                     s = 1.0 - u - v;
        constexpr double eps = -1e-9; // points on shared edges belong to either triangle
        if (u < eps || v < eps || s < eps) continue;
        if (gradient) {
            // The triangle's plane z = A.z + g . (p - a).
            const glm::dvec3 n = glm::dvec3((B.y - A.y) * (C.z - A.z) - (B.z - A.z) * (C.y - A.y),
                                            (B.z - A.z) * (C.x - A.x) - (B.x - A.x) * (C.z - A.z),
                                            (B.x - A.x) * (C.y - A.y) - (B.y - A.y) * (C.x - A.x));
            *gradient = {-n.x / n.z, -n.y / n.z};
        }
        return u * A.z + v * B.z + s * C.z;
    }
    return std::nullopt;
}

std::pair<double, double> MeshHeightField::bounds(double x0, double x1, double y0,
                                                  double y1) const {
    const auto [i0, j0] = cell_of(x0, y0);
    const auto [i1, j1] = cell_of(x1, y1);
    std::pair<double, double> r{1e300, -1e300};
    if (i0 == i1 && j0 == j1) {
        // Within one cell: the surface over the box is made of pieces of the planes of
        // the triangles meeting the box; a plane's extremes over the box are at its
        // corners. This range shrinks with the box, unlike the cell's.
        for (std::uint32_t t : cells_[std::size_t(j0) * nx_ + i0]) {
            const Plane& p = planes_[t];
            if (p.x1 < x0 || p.x0 > x1 || p.y1 < y0 || p.y0 > y1) continue;
            for (const double x : {x0, x1})
                for (const double y : {y0, y1}) {
                    const double z = p.z0 + p.gx * x + p.gy * y;
                    r.first = std::min(r.first, z);
                    r.second = std::max(r.second, z);
                }
        }
        if (r.first <= r.second) return r;
    }
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
            const auto& z = cell_z_[std::size_t(j) * nx_ + i];
            r.first = std::min(r.first, z.first);
            r.second = std::max(r.second, z.second);
        }
    return r;
}

} // namespace fird
