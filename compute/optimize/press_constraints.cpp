#include "press_constraints.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "model/press_measures.hpp"
#include "model/surface.hpp"

namespace fird {

namespace {

// The constraints of x's reflector; none where its values make no surface.
std::vector<ConstraintCheck> checks_at(const Scene& scene, const ParameterSpace& space,
                                       const std::vector<double>& x) {
    try {
        const ReflectorDesc r = space.reflector(scene.reflector, x);
        return constraint_checks(Surface::make(r, scene.holder), r.constraints);
    } catch (const std::invalid_argument&) {
        return {};
    }
}

// The points the refusal looks at: the start, the centre, the corners (or the ends).
std::vector<std::vector<double>> probe_points(const ParameterSpace& s) {
    std::vector<std::vector<double>> out{s.start, {}};
    for (std::size_t k = 0; k < s.size(); ++k)
        out[1].push_back(0.5 * (s.lo[k] + s.hi[k]));
    if (s.size() <= kCornersUpTo) {
        for (std::uint64_t mask = 0; mask < (1ull << s.size()); ++mask) {
            std::vector<double> x(s.size());
            for (std::size_t k = 0; k < s.size(); ++k)
                x[k] = (mask >> k) & 1 ? s.hi[k] : s.lo[k];
            out.push_back(std::move(x));
        }
    } else {
        for (std::size_t k = 0; k < s.size(); ++k)
            for (const double end : {s.lo[k], s.hi[k]}) {
                std::vector<double> x = s.start;
                x[k] = end;
                out.push_back(std::move(x));
            }
    }
    return out;
}

} // namespace

void refuse_unmeetable_constraints(const Scene& scene, const ParameterSpace& space) {
    const ConstraintsDesc& c = scene.reflector.constraints;
    if (!c.any()) return;
    struct Closest {
        bool met = false;
        double violation = std::numeric_limits<double>::infinity();
        double value = 0.0, limit = 0.0;
        std::vector<double> x;
    };
    std::map<std::string, Closest> closest;
    const std::vector<std::vector<double>> points = probe_points(space);
    for (const std::vector<double>& x : points) {
        for (const ConstraintCheck& k : checks_at(scene, space, x)) {
            Closest& best = closest[k.name];
            if (k.met) best.met = true;
            if (k.violation < best.violation) best = {best.met, k.violation, k.value, k.limit, x};
        }
        // Each met somewhere: nothing to refuse (up to 2^8 points spared). A point whose
        // values make no surface gives no checks and settles nothing.
        const std::size_t given = std::size_t(c.max_slope_deg.has_value()) +
                                  c.min_radius_mm.has_value() + c.max_depth_mm.has_value();
        if (closest.size() == given &&
            std::all_of(closest.begin(), closest.end(), [](const auto& e) { return e.second.met; }))
            return;
    }
    for (const auto& [name, best] : closest)
        if (!best.met)
            throw std::invalid_argument(fmt::format(
                "{}: [reflector.constraints] {} = {:g}: no candidate looked at meets it (the "
                "start, the box's centre and its {}; closest {:.4g} at {}); loosen it or move "
                "the bounds",
                scene.path, name, best.limit,
                space.size() <= kCornersUpTo ? "corners" : "parameters' ends", best.value,
                space.text(best.x)));
}

std::vector<ConstraintAtOptimum> constraints_at(const Scene& scene, const ParameterSpace& space,
                                                const std::vector<double>& x) {
    std::vector<ConstraintAtOptimum> out;
    for (const ConstraintCheck& c : checks_at(scene, space, x))
        out.push_back({c.name, c.value, c.limit, c.met, false, {}});
    if (out.empty()) return out;
    for (std::size_t k = 0; k < space.size(); ++k)
        for (const int sign : {+1, -1}) {
            std::vector<double> n = x;
            n[k] = std::clamp(x[k] + sign * space.step[k], space.lo[k], space.hi[k]);
            if (n[k] == x[k]) continue;
            for (const ConstraintCheck& c : checks_at(scene, space, n)) {
                auto it = std::find_if(out.begin(), out.end(), [&](const ConstraintAtOptimum& o) {
                    return o.name == c.name;
                });
                if (it == out.end() || it->active || c.met) continue;
                it->active = true;
                it->active_by = fmt::format("{} {} 1 step", space.names[k], sign > 0 ? "+" : "-");
            }
        }
    return out;
}

} // namespace fird
