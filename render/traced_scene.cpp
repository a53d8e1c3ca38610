#include "traced_scene.hpp"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/desired_farfield.hpp"
#include "model/source.hpp"
#include "optimize/parameter_space.hpp"

namespace fird::render {

TracedScene trace_for_views(const vk::Context& ctx, const Scene& input, const TraceForViews& o) {
    TracedScene t;
    t.scene = input;
    if (o.rays) t.scene.trace.rays = *o.rays;
    const auto names = family_parameters(t.scene.reflector.family);
    for (const auto& [k, v] : o.parameters) {
        if (std::find(names.begin(), names.end(), k) == names.end() &&
            !t.scene.reflector.bspline.groups.count(k))
            throw std::invalid_argument(fmt::format("--parameters {}: not a parameter of the {} "
                                                    "family",
                                                    k, family_name(t.scene.reflector.family)));
        t.scene.reflector.parameters[k] = v;
    }
    const Feasibility f = candidate_feasibility(t.scene, t.scene.reflector);
    if (!f.feasible) throw std::invalid_argument("--parameters: " + f.reason);
    const Scene& s = t.scene;
    t.evaluator = std::make_unique<Evaluator>(ctx, s, scene_fidelity(s));
    const CandidateResult r = t.evaluator->evaluate(s.reflector);
    t.tally = r.run.tally;
    t.farfield.obtained = t.evaluator->farfield();
    t.farfield.title = s.name;
    if (s.target.kind != TargetDesc::Kind::None) {
        DesiredFarField d = desired_farfield(ctx, s, r.farfield_lm);
        t.evaluator->set_desired(d.farfield);
        t.farfield.l2_lm = t.evaluator->compare();
        t.farfield.desired = std::move(d.farfield);
    }
    FastTracer& tracer = t.evaluator->tracer();
    ViewportContent& v = t.viewport;
    v.holder = s.holder;
    v.source = s.source;
    v.quadtree = tracer.read_quadtree();
    v.heights = &tracer.heights_buffer();
    v.heights_origin_z_mm = tracer.frame_origin().z;
    v.gradients = &tracer.gradients_buffer();
    v.width = tracer.heightfield_width();
    v.height = tracer.heightfield_height();
    const auto level0 = v.quadtree.begin() + std::ptrdiff_t(std::size_t(v.width) * v.height);
    const auto [lo, hi] = std::minmax_element(v.quadtree.begin(), level0);
    v.z_lo_mm = *lo;
    v.z_hi_mm = *hi;
    const auto rays = sample_effective_rays(s, o.paths);
    if (o.pick && *o.pick >= rays.size())
        throw std::invalid_argument(fmt::format("--pick-ray {}: there are {} sample rays (0 to {})",
                                                *o.pick, rays.size(), rays.size() - 1));
    v.paths = tracer.trace_paths(rays, o.pick.value_or(0), o.pick ? &v.walk : nullptr);
    v.picked = o.pick;
    return t;
}

} // namespace fird::render
