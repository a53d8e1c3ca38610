// The cases of fird stress, built in code.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "fastpath/scene_params.hpp"
#include "io/scene_file.hpp"
#include "stress/stress.hpp"

namespace fird {

namespace {

Scene base_scene(const std::string& name, Family family, std::map<std::string, double> params,
                 Holder holder, SourceDesc source, std::uint32_t bounces, std::uint32_t hf = 400) {
    Scene s;
    s.path = "stress:" + name;
    s.name = name;
    s.holder = holder;
    s.source = source;
    s.reflector.family = family;
    s.reflector.parameters = std::move(params);
    s.trace.rays = 20000;
    s.trace.seed = 11;
    s.trace.max_bounces = bounces;
    s.trace.heightfield_w = s.trace.heightfield_h = hf;
    s.trace.farfield_w = 360;
    s.trace.farfield_h = 180;
    return s;
}

SourceDesc point(glm::dvec3 at) {
    return {.kind = SourceKind::Point,
            .center_mm = at,
            .emittance = Emittance::Isotropic,
            .flux_lm = 100.0};
}
SourceDesc sphere(glm::dvec3 at, double r) {
    return {.kind = SourceKind::Sphere,
            .center_mm = at,
            .radius_mm = r,
            .emittance = Emittance::Cosine,
            .flux_lm = 1100.0};
}

// Model A's paraboloid scaled by `k` about the origin and moved by `offset`.
Scene paraboloid(const std::string& name, double k, glm::dvec3 offset, std::uint32_t hf = 400) {
    return base_scene(name, Family::Paraboloid,
                      {{"fx", 15.0 * k},
                       {"fy", 10.0 * k},
                       {"z0", -12.0 * k + offset.z},
                       {"cx", offset.x},
                       {"cy", offset.y}},
                      {glm::dvec3(-30, -20, -20) * k + offset, glm::dvec3(30, 20, 0) * k + offset},
                      point(glm::dvec3(0, 0, -1) * k + offset), 1, hf);
}

// Model B's cup (5 bounces), moved by `offset`.
Scene cup(const std::string& name, double p, HitMode mode, glm::dvec3 offset = {0, 0, 0}) {
    Scene s = base_scene(name, Family::Cup,
                         {{"a", 4.0},
                          {"b", 3.0},
                          {"p", p},
                          {"h", 6.0},
                          {"z0", -6.0 + offset.z},
                          {"cx", 5.0 + offset.x},
                          {"cy", -5.0 + offset.y}},
                         {glm::dvec3(0, -10, -6) + offset, glm::dvec3(10, 0, 0) + offset},
                         sphere(glm::dvec3(5, -5, -5) + offset, 0.5), 5);
    s.trace.hit_mode = mode;
    return s;
}

// Model C's fluted cup (6 bounces), moved by `offset`.
Scene fluted(const std::string& name, double w, HitMode mode, glm::dvec3 offset = {0, 0, 0}) {
    Scene s = base_scene(name, Family::FlutedCup,
                         {{"a", 4.0},
                          {"p", 2.0},
                          {"h", 6.0},
                          {"w", w},
                          {"z0", -6.0 + offset.z},
                          {"cx", 5.0 + offset.x},
                          {"cy", 5.0 + offset.y}},
                         {glm::dvec3(0, 0, -6) + offset, glm::dvec3(10, 10, 0) + offset},
                         sphere(glm::dvec3(5, 5, 0) + offset, 1.0), 6);
    s.trace.hit_mode = mode;
    return s;
}

// A dish triangulated from the paraboloid z = -6 + r^2 / 8 on a 40 x 40 grid, as OBJ.
std::string write_dish(const std::string& dir) {
    namespace fs = std::filesystem;
    fs::create_directories(dir);
    const std::string path = (fs::path(dir) / "stress_dish.obj").string();
    std::ofstream out(path);
    constexpr int n = 40;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = -10.0 + 20.0 * i / n, y = -10.0 + 20.0 * j / n;
            out << fmt::format("v {} {} {}\n", x, y, std::min(0.0, -6.0 + (x * x + y * y) / 8.0));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
            out << fmt::format("f {} {} {}\nf {} {} {}\n", a, b, d, a, d, c);
        }
    return path;
}

// Rays with slope s over the flat mirror, meeting it about 10 mm downstream.
std::vector<Ray> grazing_rays(double slope, double z_plane) {
    std::vector<Ray> rays;
    for (int k = 0; k < 400; ++k) {
        const double y = -15.0 + 30.0 * (k + 0.5) / 400.0;
        const glm::dvec3 d = glm::normalize(glm::dvec3(1.0, 0.013 * (k % 7 - 3), -slope));
        rays.push_back({{-15.0 + 0.01 * (k % 13), y, z_plane + 10.0 * slope}, d});
    }
    return rays;
}

// Rays straight down through texel corners, and along texel edges, of a W x H field.
std::vector<Ray> lattice_rays(const Scene& s, bool along_edges) {
    std::vector<Ray> rays;
    const Holder& h = s.holder;
    const double tx = (h.max_mm.x - h.min_mm.x) / s.trace.heightfield_w;
    const double ty = (h.max_mm.y - h.min_mm.y) / s.trace.heightfield_h;
    for (int k = 0; k < 800; ++k) {
        const int i = 7 + (k * 37) % int(s.trace.heightfield_w - 14);
        const int j = 7 + (k * 53) % int(s.trace.heightfield_h - 14);
        const double x = h.min_mm.x + i * tx, y = h.min_mm.y + j * ty;
        if (!along_edges)
            rays.push_back({{x, y, h.max_mm.z - 0.5}, {0.0, 0.0, -1.0}});
        else if (k % 2)
            rays.push_back(
                {{h.min_mm.x + 0.5, y, h.max_mm.z - 1.0}, glm::normalize(glm::dvec3(1, 0, -0.35))});
        else
            rays.push_back(
                {{x, h.min_mm.y + 0.5, h.max_mm.z - 1.0}, glm::normalize(glm::dvec3(0, 1, -0.35))});
    }
    return rays;
}

} // namespace

std::vector<StressCase> stress_cases(const vk::Context& ctx, const std::string& scratch) {
    std::vector<StressCase> cases;
    // Grazing rays over a flat mirror: a float height error e moves the hit by e / slope,
    // so the tolerance grows as the slope falls (float rounding of z = -2 is ~2.4e-7 mm).
    const Scene flat =
        base_scene("flat mirror", Family::Plane,
                   {{"z0", -2.0}, {"sx", 0.0}, {"sy", 0.0}, {"cx", 0.0}, {"cy", 0.0}},
                   {{-20, -20, -10}, {20, 20, 4}}, point({0, 0, 3}), 1);
    for (int e = 2; e <= 6; ++e) {
        const double slope = std::pow(10.0, -e);
        const double texel = 40.0 / 400.0;
        cases.push_back({fmt::format("grazing, slope 1e-{}", e), flat, grazing_rays(slope, -2.0), 0,
                         std::max(0.25, 8.0 * 2.4e-7 / slope / texel)});
    }
    const Scene a = paraboloid("paraboloid", 1.0, {0, 0, 0});
    cases.push_back({"texel corners, straight down", a, lattice_rays(a, false)});
    cases.push_back({"along texel edges, axis-parallel", a, lattice_rays(a, true)});
    cases.push_back({"paraboloid (source rays)", a});
    Scene strict = a;
    strict.name = "paraboloid, strict policy, 3 bounces";
    strict.trace.bounce_policy = BouncePolicy::Strict;
    strict.trace.max_bounces = 3;
    cases.push_back({strict.name, strict});
    Scene tilted = flat;
    tilted.name = "tilted plane";
    tilted.reflector.parameters["sx"] = 0.3;
    tilted.reflector.parameters["sy"] = -0.2;
    cases.push_back({tilted.name, tilted});
    for (HitMode m : {HitMode::Refined, HitMode::Paper}) {
        const char* mode = m == HitMode::Paper ? "paper" : "refined";
        // The paper hit mode's surface is flat-topped columns: its hits are a texel off
        // on steep walls by design (docs/benchmarks.md).
        const double tol = m == HitMode::Paper ? 6.0 : 0.25;
        const bool paths = m == HitMode::Refined;
        const std::string paper_note = "paths not compared: the paper's texel columns";
        cases.push_back({.name = fmt::format("cup, p = 4, {}", mode),
                         .scene = cup("cup", 4.0, m),
                         .hit_tolerance_texels = tol,
                         .compare_paths = paths,
                         .note = paths ? "" : paper_note});
        // Five bounces between near-vertical walls, six among the flutes (whose apex is a
        // kink): the default direction bound holds for all but the rays of kMaxDirection-
        // Outliers, since the refined mode reflects about the true normal.
        cases.push_back({.name = fmt::format("cup, steep walls p = 8, {}", mode),
                         .scene = cup("cup p8", 8.0, m),
                         .hit_tolerance_texels = tol,
                         .compare_paths = paths,
                         .note = paths ? "" : paper_note});
        cases.push_back({.name = fmt::format("fluted cup, w = 1 (its bound), {}", mode),
                         .scene = fluted("fluted", 1.0, m),
                         .hit_tolerance_texels = tol,
                         .compare_paths = paths,
                         .note = paths ? "" : paper_note});
    }
    Scene bspline = base_scene("bspline dish", Family::BSpline, {}, {{0, 0, -6}, {10, 10, 0}},
                               sphere({5, 5, 0.2}, 0.5), 3, 300);
    bspline.reflector.bspline = {
        .nx = 4,
        .ny = 4,
        .heights_mm = {-1, -1, -1, -1, -1, -5, -5, -1, -1, -5, -5, -1, -1, -1, -1, -1}};
    cases.push_back({bspline.name, bspline});
    // A profile bowl about (1, -1), near the paraboloid -5 + r^2 / 16 whose focus the sphere
    // sits at; its rim clamped by the holder's top.
    Scene profile = base_scene("profile bowl", Family::Profile,
                               {{"z0", -5.0}, {"cx", 1.0}, {"cy", -1.0}, {"radius_mm", 9.0}},
                               {{-10, -10, -6}, {10, 10, 0}}, sphere({1, -1, -1}, 0.4), 3, 300);
    profile.reflector.bspline = {.nx = 6, .ny = 1, .heights_mm = {0, 0.2, 0.8, 1.8, 3.25, 5.1}};
    cases.push_back({profile.name, profile});
    Scene mesh = base_scene("triangle mesh dish", Family::Mesh, {}, {{-10, -10, -6}, {10, 10, 0}},
                            point({0, 0, -4}), 2);
    mesh.reflector.mesh = {
        .file = "stress_dish.obj", .resolved_path = write_dish(scratch), .unit_mm = 1.0};
    // The refined mode reflects about the facet under the hit texel's centre, as the exact
    // mesh does about the facet hit: directions agree but for rays within a texel of a
    // facet edge (~2 % of this 40 x 40 grid's area at 0.05 mm texels), whose hit texel may
    // belong to the neighbouring facet. Their share is under 1 %, so the p99 bound is the
    // default's; the hits' tolerance covers the patch's cut across facet edges.
    cases.push_back({.name = mesh.name, .scene = mesh, .hit_tolerance_texels = 0.5});
    // Height fields of extreme shape and size.
    for (const auto& [w, h] : {std::pair{1u, 4096u}, std::pair{4096u, 1u}, std::pair{1u, 1u}}) {
        Scene s = a;
        s.name = fmt::format("height field {} x {}", w, h);
        s.trace.heightfield_w = w;
        s.trace.heightfield_h = h;
        // One texel across: the surface is that coarse; only stability is asked of it.
        cases.push_back({.name = s.name,
                         .scene = s,
                         .compare_surface = false,
                         .note = "one texel across: stability only"});
    }
    {
        // The largest square height field the device takes: its quadtree within the
        // texel-buffer limit, its gradients within one storage-buffer binding.
        const auto& l = ctx.limits();
        const double texels = std::min(0.74 * double(l.max_texel_buffer_elements),
                                       double(l.max_storage_buffer_range) / 8.0);
        const auto side = std::uint32_t(std::min(8192.0, std::floor(std::sqrt(texels))));
        Scene s = paraboloid("largest", 1.0, {0, 0, 0}, side);
        s.name = fmt::format("height field {} x {} (the device's limit)", side, side);
        s.trace.rays = 5000;
        cases.push_back({s.name, s, {}, 500, 0.5});
    }
    cases.push_back({"tiny scene (holder 0.06 x 0.04 mm)", paraboloid("tiny", 1e-3, {0, 0, 0})});
    cases.push_back({"large scene (holder 12 x 8 m)", paraboloid("large", 200.0, {0, 0, 0})});
    cases.push_back(
        {"far from the origin (holder at x = 1e5 mm)", paraboloid("far", 1.0, {1e5, 0, 0})});
    cases.push_back(
        {"far from the origin (holder at z = -1e5 mm)", paraboloid("deep", 1.0, {0, 0, -1e5})});
    // Several bounces far from the origin: the fast path works relative to the holder's
    // centre (scene_params.hpp), so these must trace as the cup and fluted cup at home do.
    cases.push_back({.name = "cup, 5 bounces, holder at (1e5, 1e5, 1e5) mm",
                     .scene = cup("far cup", 4.0, HitMode::Refined, {1e5, 1e5, 1e5})});
    cases.push_back({.name = "fluted cup, 6 bounces, holder at (-1e5, 1e5, -1e5) mm",
                     .scene = fluted("far fluted", 1.0, HitMode::Refined, {-1e5, 1e5, -1e5})});
    for (StressCase& c : cases)
        validate_scene(c.scene);
    return cases;
}

} // namespace fird
