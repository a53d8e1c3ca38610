// A fixed reflector given as a triangle mesh that is the graph of z = f(x, y) over the
// holder rectangle: loaded from OBJ or STL, checked, and located by a 2D grid.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene.hpp"

namespace fird {

struct TriangleMesh {
    std::vector<glm::dvec3> vertices; // mm
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// Reads OBJ (v / f, polygons fanned, negative indices, v/vt/vn forms) or STL (binary
// or ASCII), scaling coordinates by unit_mm. Throws std::runtime_error "file:line: ..."
// (or "file: triangle N: ...") on malformed input.
TriangleMesh load_mesh(const std::string& path, double unit_mm);
// The same from the file's bytes (`path` names it in messages and picks the format).
TriangleMesh parse_mesh(const std::string& path, const std::string& bytes, double unit_mm);

// The mesh as a height function: point location by a uniform xy grid of triangles.
class MeshHeightField {
  public:
    // Throws std::invalid_argument naming where the mesh is not a graph over the
    // holder rectangle (a fold or overhang: two triangles over one point; a hole: none).
    MeshHeightField(TriangleMesh mesh, const Holder& holder, const std::string& name);

    // Height and gradient of the triangle over (x, y); nullopt outside the mesh.
    std::optional<double> height(double x, double y, glm::dvec2* gradient = nullptr) const;
    // The range of heights of the triangles whose xy bounds meet the box.
    std::pair<double, double> bounds(double x0, double x1, double y0, double y1) const;
    const TriangleMesh& mesh() const { return mesh_; }

  private:
    std::pair<int, int> cell_of(double x, double y) const;
    TriangleMesh mesh_;
    Holder holder_;
    int nx_ = 1, ny_ = 1;
    std::vector<std::vector<std::uint32_t>> cells_;
    std::vector<std::pair<double, double>> cell_z_; // min, max of z over the cell's triangles
    struct Plane {
        double z0, gx, gy;     // z = z0 + gx x + gy y
        double x0, x1, y0, y1; // the triangle's xy bounds
    };
    std::vector<Plane> planes_;
};

} // namespace fird
