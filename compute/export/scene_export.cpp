#include "scene_export.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkStructuredGrid.h>
#include <vtkUnstructuredGrid.h>

#include "evaluation/desired_farfield.hpp"
#include "evaluation/evaluator.hpp"
#include "export/datasets.hpp"
#include "export/vtk_file.hpp"
#include "io/atomic_file.hpp"
#include "model/source.hpp"
#include "optimize/parameter_space.hpp"

namespace fird {

namespace {

// The coarsest levels that stay within `budget` boxes.
std::vector<std::uint32_t> coarsest_levels(const QuadtreeLayout& q, std::uint32_t count) {
    std::vector<std::uint32_t> levels;
    for (std::uint32_t k = 0; k < count && k < q.levels; ++k)
        levels.push_back(q.levels - 1 - k);
    return levels;
}

} // namespace

ExportReport export_scene(const vk::Context& ctx, const Scene& input, const ExportOptions& o,
                          const std::string& dir) {
    namespace fs = std::filesystem;
    Scene scene = input;
    if (o.rays) scene.trace.rays = o.rays;
    scene.reflector = overridden(scene, o.parameters);
    if (o.paths > kMaxPaths)
        throw std::invalid_argument(
            fmt::format("--paths {}: at most {} ray paths are written", o.paths, kMaxPaths));
    ExportReport report;
    const QuadtreeLayout q = quadtree_layout(scene.trace.heightfield_w, scene.trace.heightfield_h);
    std::uint32_t levels = o.levels;
    if (levels == 0) {
        while (levels < q.levels && vtkio::quadtree_box_count(q, coarsest_levels(q, levels + 1)) <=
                                        kDefaultQuadtreeBoxes)
            ++levels;
    } else if (levels > q.levels) {
        throw std::invalid_argument(fmt::format("--levels {}: the {} x {} height field has {} "
                                                "quadtree levels",
                                                levels, q.w[0], q.h[0], q.levels));
    }
    if (vtkio::quadtree_box_count(q, coarsest_levels(q, levels)) > kMaxQuadtreeBoxes) {
        std::uint32_t fit = 0;
        while (vtkio::quadtree_box_count(q, coarsest_levels(q, fit + 1)) <= kMaxQuadtreeBoxes)
            ++fit;
        report.notes.push_back(fmt::format(
            "--levels {}: {} boxes would pass the limit of {} (about {} MB); wrote the "
            "coarsest {} levels",
            levels, vtkio::quadtree_box_count(q, coarsest_levels(q, levels)), kMaxQuadtreeBoxes,
            vtkio::quadtree_box_count(q, coarsest_levels(q, levels)) * 120 / 1000000, fit));
        levels = fit;
    }
    report.quadtree_levels = levels;

    create_output_directory(dir);
    Evaluator ev(ctx, scene, scene_fidelity(scene));
    ev.set_count_texel_hits(true);
    const CandidateResult run = ev.evaluate(scene.reflector);
    report.tally = run.run.tally;
    report.energy_per_ray_lm = run.run.energy_per_ray_lm;
    const FarField farfield = ev.farfield();
    std::optional<FarField> target;
    if (scene.target.kind != TargetDesc::Kind::None)
        target = desired_farfield(ctx, scene, run.farfield_lm).farfield;
    const TexelHits hits = ev.read_texel_hits();
    const std::vector<float> tree = ev.read_quadtree();
    const std::vector<glm::vec2> gradients = ev.read_gradients();
    const std::vector<float> heights(tree.begin(), tree.begin() + std::ptrdiff_t(hits.all.size()));
    // The sampled rays under their rayset indices (a finish's draws are keyed on them).
    const std::vector<std::uint64_t> indices = sample_effective_ray_indices(scene, o.paths);
    std::vector<Ray> sampled;
    for (const std::uint64_t i : indices)
        sampled.push_back(
            emit_ray(scene.source, scene.trace.sampler, scene.trace.seed, i, scene.trace.rays));
    const auto paths = ev.trace_paths(sampled, &indices);

    const auto write = [&](const std::string& name, vtkDataObject* data) {
        report.files.push_back({name, vtkio::write_dataset((fs::path(dir) / name).string(), data)});
    };
    write("reflector.vts",
          vtkio::reflector_grid(scene.holder, hits.width, hits.height, heights, gradients, &hits));
    write("quadtree.vtu", vtkio::quadtree_boxes(scene.holder, q, tree, coarsest_levels(q, levels)));
    write("rays.vtp", vtkio::ray_paths(paths, run.run.energy_per_ray_lm));
    const FarField* t = target ? &*target : nullptr;
    write("farfield.vti", vtkio::farfield_image(farfield, t));
    write("farfield_sphere.vtp", vtkio::farfield_sphere(farfield, t));
    write("source.vtp", vtkio::source_surface(scene.source));
    write("holder.vtp", vtkio::holder_box(scene.holder));
    // The collection lists the scene's objects in the holder's frame (not the far field
    // image, whose axes are degrees).
    std::vector<vtkio::CollectionEntry> entries;
    int part = 0;
    for (const char* name : {"reflector.vts", "quadtree.vtu", "rays.vtp", "source.vtp",
                             "holder.vtp", "farfield_sphere.vtp"})
        entries.push_back({name, 0.0, part++});
    report.files.push_back(
        {"scene.pvd", vtkio::write_collection((fs::path(dir) / "scene.pvd").string(), entries)});
    return report;
}

ExportReport export_search_reflectors(const Scene& scene, const SearchResult& r,
                                      const std::string& dir) {
    namespace fs = std::filesystem;
    ExportReport report;
    const std::uint32_t w = std::min<std::uint32_t>(scene.trace.heightfield_w, 400);
    const std::uint32_t h = std::min<std::uint32_t>(scene.trace.heightfield_h, 400);
    create_output_directory((fs::path(dir) / "reflectors").string());
    std::vector<vtkio::CollectionEntry> entries;
    double best = 0.0;
    std::uint32_t stage = ~0u;
    for (const Candidate& c : r.history) {
        if (!c.feasible) continue;
        if (c.stage != stage) stage = c.stage, best = HUGE_VAL; // l2 of another fidelity
        if (!(c.score < best)) continue;                        // what the search ranks by
        best = c.score;
        ReflectorDesc reflector = scene.reflector;
        for (std::size_t k = 0; k < r.names.size(); ++k)
            reflector.parameters[r.names[k]] = c.x[k];
        const std::string name = fmt::format("reflectors/best_{:06}.vts", c.index);
        const std::uint64_t bytes =
            vtkio::write_dataset((fs::path(dir) / name).string(),
                                 vtkio::surface_grid(Surface::make(reflector, scene.holder), w, h));
        report.files.push_back({name, bytes});
        entries.push_back({name, double(c.index), 0});
    }
    report.files.push_back(
        {"reflectors.pvd",
         vtkio::write_collection((fs::path(dir) / "reflectors.pvd").string(), entries)});
    return report;
}

} // namespace fird
