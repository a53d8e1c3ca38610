// Reflector families as height functions z = f(x, y) over the holder rectangle, clamped
// to the holder's z range: value, analytic gradient, and a conservative height range
// over any axis-aligned box (used by the reference tracer to bracket roots safely).
#pragma once

#include <memory>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>

#include "scene.hpp"

namespace fird {

struct HeightRange {
    double lo;
    double hi;
};

struct PlaneFn {
    double z0, sx, sy, cx, cy;
};
struct ParaboloidFn {
    double fx, fy, z0, cx, cy;
};
struct CupFn {
    double a, b, p, h, z0, cx, cy;
};
struct FlutedCupFn {
    double a, p, h, w, z0, cx, cy;
};
class MeshHeightField;
struct MeshFn {
    std::shared_ptr<const MeshHeightField> field;
};
struct BSplineFn {
    int nx, ny;
    double x0, y0, dx, dy; // control height (i, j) sits at (x0 + i dx, y0 + j dy)
    std::vector<double> heights;
};
// z = z0 + f(r), r the distance from (cx, cy): f the uniform cubic B-spline with knots at
// r_k = k spacing (k = 0 .. spans) through the profile's heights, held at f(r_spans) beyond.
// control[k + 1] is the control point c_k, k = -1 .. spans + 1 (profile_control_points).
struct ProfileFn {
    double z0, cx, cy, spacing;
    int spans;
    std::vector<double> control;
};

// The control points c_-1 .. c_n (n = heights - 1) of the uniform cubic B-spline f through
// heights h_0 .. h_n at r_0 .. r_n: f(r_k) = (c_k-1 + 4 c_k + c_k+1) / 6 = h_k, with
// f'(0) = 0 (c_-1 = c_1: a surface of revolution without a cone's tip on its axis) and
// f''(r_n) = 0 (c_n+1 = 2 c_n - c_n-1, the natural end). A tridiagonal system, solved
// exactly (Thomas' algorithm; the matrix is diagonally dominant). Needs two heights.
std::vector<double> profile_control_points(const std::vector<double>& heights_mm);

class Surface {
  public:
    // Throws std::invalid_argument naming the parameter when a value is out of range, or
    // where a mesh is not a height field; std::runtime_error for an unreadable mesh.
    static Surface make(const ReflectorDesc& reflector, const Holder& holder);

    double height(double x, double y) const;       // clamped to the holder's z range
    glm::dvec2 gradient(double x, double y) const; // of the clamped surface
    HeightRange bounds(double x0, double x1, double y0, double y1) const; // clamped, conservative
    const Holder& holder() const { return holder_; }

    // Unclamped ("raw") family function and its gradient.
    double raw(double x, double y) const;
    glm::dvec2 raw_gradient(double x, double y) const;

    // The family function itself, for exports that write it exactly (a B-spline as CAD).
    using Fn =
        std::variant<PlaneFn, ParaboloidFn, CupFn, FlutedCupFn, BSplineFn, MeshFn, ProfileFn>;
    const Fn& function() const { return fn_; }

  private:
    Surface(Fn fn, const Holder& holder) : fn_(std::move(fn)), holder_(holder) {}
    Fn fn_;
    Holder holder_;
};

// Whether control height (i, j) of an nx x ny grid belongs to the group.
bool in_control_group(const ControlGroup& group, int i, int j, int nx, int ny);

// Applies the B-spline's parameters (group values) to its control heights.
std::vector<double> bspline_heights(const BSplineDesc& spline,
                                    const std::map<std::string, double>& parameters);

} // namespace fird
