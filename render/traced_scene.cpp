#include "traced_scene.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/desired_farfield.hpp"
#include "fastpath/picked_ray.hpp"
#include "model/design_parameters.hpp"
#include "model/source.hpp"
#include "optimize/parameter_space.hpp"

namespace fird::render {

TracedScene trace_for_views(const vk::Context& ctx, const Scene& input, const TraceForViews& o) {
    TracedScene t;
    t.scene = input;
    if (o.rays) t.scene.trace.rays = *o.rays;
    const auto names = family_parameters(t.scene.reflector.family);
    for (const auto& [k, v] : o.parameters) {
        if (is_source_parameter(k)) {
            try {
                (void)moved_source(t.scene.source, {{source_parameter_key(k), v}});
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument("--parameters " + k + ": " + e.what());
            }
        } else if (std::find(names.begin(), names.end(), k) == names.end() &&
                   !t.scene.reflector.bspline.groups.count(k))
            throw std::invalid_argument(fmt::format("--parameters {}: not a parameter of the {} "
                                                    "family",
                                                    k, family_name(t.scene.reflector.family)));
    }
    // Reflector values into the reflector, the source's ([source.optimize]) into the source.
    apply_design_parameters(t.scene, o.parameters);
    const Feasibility f = traceable(t.scene, t.scene.reflector);
    if (!f.feasible) throw std::invalid_argument("--parameters: " + f.reason);
    const Scene& s = t.scene;
    t.evaluator = std::make_unique<Evaluator>(ctx, s, scene_fidelity(s));
    const CandidateResult r = t.evaluator->evaluate(s.reflector);
    t.tally = r.run.tally;
    t.farfield.obtained = t.evaluator->farfield();
    t.farfield.title = s.name;
    if (s.target.kind != TargetDesc::Kind::None) {
        const bool reuse = o.target_farfield && s.target.kind == TargetDesc::Kind::Reflector &&
                           o.target_farfield->width == t.farfield.obtained.width &&
                           o.target_farfield->height == t.farfield.obtained.height;
        FarField desired =
            reuse ? *o.target_farfield : desired_farfield(ctx, s, r.farfield_lm).farfield;
        t.evaluator->set_desired(desired);
        t.farfield.l2_lm = t.evaluator->compare();
        t.farfield.desired = std::move(desired);
    }
    // The press's view: the steepest point (a mesh's heights are the evaluator's alone: it
    // is not read again here), and the constraints met or broken.
    if (s.reflector.family != Family::Mesh) {
        const Surface surface = Surface::make(s.reflector, s.holder);
        const PressMeasures press = press_measures(surface);
        const auto on_surface = [&](glm::dvec2 at) {
            return glm::dvec3(at, surface.height(at.x, at.y));
        };
        if (press.any_unclamped) t.viewport.steepest_mm = on_surface(press.max_slope_at_mm);
        // A plane has no bend to mark (no radius); a kink's radius is 0.
        if (std::isfinite(press.min_radius_mm)) {
            t.viewport.tightest_mm = on_surface(press.min_radius_at_mm);
            t.viewport.min_radius_mm = press.min_radius_mm;
        }
        if (s.reflector.constraints.any())
            t.constraints = constraint_checks(surface, s.reflector.constraints);
    }
    ViewportContent& v = t.viewport;
    v.holder = s.holder;
    v.source = s.source;
    v.quadtree = t.evaluator->read_quadtree();
    const Evaluator::DeviceHeightField device = t.evaluator->device_heightfield();
    v.heights = device.heights;
    v.heights_origin_z_mm = device.origin_z_mm;
    v.gradients = device.gradients;
    v.width = device.width;
    v.height = device.height;
    const auto level0 = v.quadtree.begin() + std::ptrdiff_t(std::size_t(v.width) * v.height);
    const auto [lo, hi] = std::minmax_element(v.quadtree.begin(), level0);
    v.z_lo_mm = *lo;
    v.z_hi_mm = *hi;
    t.rayset_rays = o.rayset_rays.value_or(s.trace.rays);
    const Scene rayset = rayset_scene(t);
    const auto indices = sample_effective_ray_indices(rayset, o.paths);
    std::vector<Ray> rays;
    for (const std::uint64_t i : indices)
        rays.push_back(emit_ray(s.source, s.trace.sampler, s.trace.seed, i, t.rayset_rays));
    v.paths = t.evaluator->trace_paths(rays, &indices);
    for (std::size_t k = 0; k < v.paths.size(); ++k)
        v.paths[k].ray_index = indices[k];
    if (o.pick) {
        try {
            v.picked = t.evaluator->pick_ray(rayset, *o.pick);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(std::string("--pick-ray: ") + e.what());
        }
    }
    return t;
}

Scene rayset_scene(const TracedScene& traced) {
    Scene rayset = traced.scene;
    rayset.trace.rays = traced.rayset_rays;
    return rayset;
}

PickedRay pick_ray(const TracedScene& traced, std::uint64_t index) {
    return traced.evaluator->pick_ray(rayset_scene(traced), index);
}

} // namespace fird::render
