// The scene: plain data read from a scene file (DESIGN.md §5). Units: mm, lumens.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "farfield/farfield.hpp"

namespace fird {

enum class SourceKind { Cylinder, Sphere, Point, Disk, Rectangle, Photometric, RayFile };

// A photometric emitter's sampling table (model/emission_table.hpp, read by
// shaders/emitter.h), shared by the copies of a scene; equal where the tables are.
struct EmissionTable {
    std::shared_ptr<const std::vector<float>> floats;
    std::uint32_t c_angles = 0; // the C angles, the first repeated at 360 degrees
    std::uint32_t gamma_angles = 0;
    bool operator==(const EmissionTable& o) const {
        return c_angles == o.c_angles && gamma_angles == o.gamma_angles &&
               (floats == o.floats || (floats && o.floats && *floats == *o.floats));
    }
};
enum class Emittance { Cosine, Isotropic };

// A ray file's index (model/ray_file_source.hpp: its layout, weights and extent), built
// once when the scene is read and shared by the copies of a scene. The file it indexes is
// SourceDesc::resolved_path, which the scenes' comparison covers; so two reads of one file
// compare equal.
struct RayFileIndex;
struct RayFileHandle {
    std::shared_ptr<const RayFileIndex> index;
    bool operator==(const RayFileHandle& o) const { return !index == !o.index; }
};

struct SourceDesc {
    SourceKind kind = SourceKind::Point;
    glm::dvec3 center_mm{0.0};
    // The emitter's local +z (shaders/emitter.h): a cylinder's axis, a cosine point's axis,
    // a disk's or rectangle's normal (its emitting side; the scene file's `normal`).
    glm::dvec3 axis{0.0, 0.0, 1.0};
    // A disk's or rectangle's local +x, perpendicular to axis (the scene file's `x_axis`;
    // by default world +x made perpendicular to the normal, or world +y where the normal
    // lies along x: model/source.hpp).
    glm::dvec3 x_axis{1.0, 0.0, 0.0};
    double length_mm = 0.0; // cylinder
    double radius_mm = 0.0; // cylinder, sphere, disk; photometric: its disk (0: a point)
    double width_mm = 0.0;  // rectangle, along x_axis
    double height_mm = 0.0; // rectangle, along axis x x_axis
    Emittance emittance = Emittance::Cosine;
    double flux_lm = 1100.0;
    std::string file;          // photometric, ray file: the file as written in the scene
    std::string resolved_path; // ... and found beside the scene
    EmissionTable table;       // photometric: its distribution, to sample
    RayFileHandle ray_file;    // ray file: its index (the rays are read as they are traced)
    bool operator==(const SourceDesc&) const = default;
};

struct Holder {
    glm::dvec3 min_mm{0.0};
    glm::dvec3 max_mm{0.0};
    bool operator==(const Holder&) const = default;
};

// Profile: rotationally symmetric about (cx, cy), z = z0 + f(r) with f a cubic spline through
// heights at radii evenly spaced from 0 to radius_mm (model/surface.hpp).
enum class Family { Plane, Paraboloid, Cup, FlutedCup, BSpline, Mesh, Profile };

struct ParameterRange {
    double min = 0.0;
    double max = 0.0;
    double step = 0.0;
    bool operator==(const ParameterRange&) const = default;
};

// A B-spline parameter moves every control height of its group to its value.
struct ControlGroup {
    enum class Kind { Point, Row, Column, Ring } kind = Kind::Point;
    int i = 0; // Point: column index; Row/Column/Ring: the index
    int j = 0; // Point: row index
    bool operator==(const ControlGroup&) const = default;
};

// A profile's heights at most (a bspline's grid is held to 1024 a side alike).
constexpr std::size_t kMaxProfileHeights = 1024;

// The bspline family's control grid, or the profile family's heights (nx of them, ny = 1,
// each its own point group h_<k>).
struct BSplineDesc {
    int nx = 0;                     // control heights along x
    int ny = 0;                     // along y
    std::vector<double> heights_mm; // row-major, ny rows of nx
    std::map<std::string, ControlGroup> groups;
    bool operator==(const BSplineDesc&) const = default;
};

struct MeshDesc {
    std::string file; // as written in the scene (relative to the scene file)
    std::string resolved_path;
    double unit_mm = 1.0;
    bool operator==(const MeshDesc&) const = default;
};

// The reflector's surface finish ([reflector.material]; shaders/material.h samples it).
enum class SpreadLobe { Gaussian, Phong };
// Beyond a few tens of degrees a lobe about the mirror direction is no longer a specular
// finish (and much of it folds at the surface); a diffuse finish is not built.
constexpr double kMaxSpread_deg = 30.0;
struct MaterialDesc {
    double reflectance = 1.0; // the share of a ray's flux each reflection keeps (0-1]
    double spread_deg = 0.0;  // the lobe's sigma about the mirror direction, per axis
    SpreadLobe lobe = SpreadLobe::Gaussian;
    bool operator==(const MaterialDesc&) const = default;
};

// What the press can form ([reflector.constraints]; model/press_measures.hpp measures
// them): each limit optional. A candidate that breaks one is infeasible in a search.
struct ConstraintsDesc {
    std::optional<double> max_slope_deg; // draft: steepest slope from the press plane
    std::optional<double> min_radius_mm; // smallest radius of curvature a tool forms
    std::optional<double> max_depth_mm;  // deepest draw
    bool any() const { return max_slope_deg || min_radius_mm || max_depth_mm; }
    bool operator==(const ConstraintsDesc&) const = default;
};

struct ReflectorDesc {
    Family family = Family::Plane;
    std::map<std::string, double> parameters;
    std::map<std::string, ParameterRange> optimize;
    BSplineDesc bspline;
    MeshDesc mesh;
    MaterialDesc material;
    ConstraintsDesc constraints;
    bool operator==(const ReflectorDesc&) const = default;
};

enum class BouncePolicy { Paper, Strict };
// stratified: Philox with its first two dimensions stratified (sampling/strata.hpp), the
// default; random: independent Philox rays; sobol: scrambled Sobol points.
enum class SamplerKind { Stratified, Random, Sobol };
enum class HitMode { Paper, Refined };
// exclude: only reflected rays reach the far field (the paper's convention); include: the
// rays that leave without touching the reflector too (DESIGN.md §2), for comparison with a
// measured luminaire file.
enum class DirectLight { Exclude, Include };

struct TraceSettings {
    std::uint64_t rays = 1000000;
    std::uint64_t seed = 1;
    std::uint32_t max_bounces = 1;
    BouncePolicy bounce_policy = BouncePolicy::Paper;
    SamplerKind sampler = SamplerKind::Stratified;
    HitMode hit_mode = HitMode::Refined;
    DirectLight direct = DirectLight::Exclude;
    std::uint32_t heightfield_w = 1200;
    std::uint32_t heightfield_h = 800;
    std::uint32_t farfield_w = 1800;
    std::uint32_t farfield_h = 900;
    bool operator==(const TraceSettings&) const = default;
};

struct TargetDesc {
    enum class Kind { None, Reflector, Photometric } kind = Kind::None;
    std::map<std::string, double> parameters; // Reflector: overrides of the reflector's
    std::uint64_t seed = 2;                   // Reflector: its own, independent seed
    std::uint64_t rays = 0;                   // Reflector: its ray count (0: [trace] rays)
    std::string file;                         // Photometric: IES / LDT path as written
    std::string resolved_path;
    bool absolute = false; // Photometric: take the file's flux as is (else scaled)
    bool operator==(const TargetDesc&) const = default;
};

// The search's defaults ([optimize]; each overridable on the command line).
// Cmaes, Xnes: pagmo2's population methods, a generation traced as one batch.
enum class SearchMethod {
    Auto,
    Grid,
    Bobyqa,
    Sbplx,
    Cobyla,
    DirectL,
    Crs2,
    Cmaes,
    Xnes,
    Levenberg
};
// How a population search samples a freed height grid (optimize/height_modes.hpp): in the
// grid's cosine modes, broad shapes first (the default), or each height on its own.
enum class HeightSampling { Modes, Independent };

struct OptimizeSettings {
    SearchMethod method = SearchMethod::Auto;
    // Rays per evaluation, one count per stage of the search: `auto` runs a stage per
    // count (empty: 1e5, 1e6 and the scene's [trace] rays); the other methods run one
    // stage with the last count (empty: the scene's [trace] rays).
    std::vector<std::uint64_t> rays;
    // What every evaluation compares (farfield.hpp): with candela_l2, every "l2" a search
    // reports (history, JSON, threshold) is that metric, in cd.
    FarFieldMetric metric = FarFieldMetric::L2;
    double threshold_lm = 0.0;              // stop once l2 falls below (0: never)
    std::uint64_t max_evaluations = 100000; // candidates, infeasible ones included
    // The weight of an optional smoothness penalty: a search minimises the metric plus
    // smoothness x the reflector's bending energy (press_measures.hpp: the integral of the
    // squared principal curvatures over the unclamped surface, dimensionless), so the
    // weight is in the metric's unit. 0: none (smoothness is then a choice of grid).
    double smoothness = 0.0;
    HeightSampling height_sampling = HeightSampling::Modes; // cmaes, xnes (and auto's)
    bool operator==(const OptimizeSettings&) const = default;
};

// The tolerances a made luminaire has ([tolerance]; fird tolerance): each a standard
// deviation of a normal error, drawn per realisation (compute/tolerance).
struct ToleranceDesc {
    std::uint64_t realisations = 32;
    glm::dvec3 source_shift_mm{0.0};     // the source's centre, per axis
    double source_tilt_deg = 0.0;        // its axis, about the scene's x and y axes each
    double surface_rms_mm = 0.0;         // a smooth random surface error's RMS ...
    double surface_correlation_mm = 0.0; // ... and its correlation length
    double reflectance_sd = 0.0;
    bool operator==(const ToleranceDesc&) const = default;
};

struct Scene {
    std::string path; // the file it came from (for messages)
    std::string name;
    SourceDesc source;
    Holder holder;
    ReflectorDesc reflector;
    TraceSettings trace;
    TargetDesc target;
    OptimizeSettings optimize;
    // [source.optimize]: the source's place as search parameters (design_parameters.hpp):
    // x_mm, y_mm, z_mm (its centre) and tilt_x_deg, tilt_y_deg (its axis turned about the
    // scene's x and y axes), each with its bounds and step.
    std::map<std::string, ParameterRange> source_optimize;
    ToleranceDesc tolerance;
    bool operator==(const Scene& o) const {
        return name == o.name && source == o.source && holder == o.holder &&
               reflector == o.reflector && trace == o.trace && target == o.target &&
               optimize == o.optimize && source_optimize == o.source_optimize &&
               tolerance == o.tolerance;
    }
};

const char* family_name(Family f);
std::optional<Family> family_from_name(const std::string& name);
// The parameter names a family needs (B-spline: its group names; mesh: none).
std::vector<std::string> family_parameters(Family f);

const char* method_name(SearchMethod m);
std::optional<SearchMethod> method_from_name(const std::string& name);
// Every method name, in the order --help lists them.
std::vector<std::string> method_names();

const char* sampler_name(SamplerKind s);
// A source's `type` in a scene file ("cylinder", ..., "photometric").
const char* source_type_name(SourceKind kind);
std::optional<SamplerKind> sampler_from_name(const std::string& name);
std::vector<std::string> sampler_names();

// The reflector the target describes: the scene's reflector with the target's values.
ReflectorDesc target_reflector(const Scene& scene);

} // namespace fird
