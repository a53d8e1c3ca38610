#include "parameter_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "model/design_parameters.hpp"
#include "model/press_measures.hpp"
#include "model/source_clearance.hpp"
#include "model/surface.hpp"

namespace fird {

namespace {

// A parameter's start: its value in the scene, or for a B-spline group without one the
// mean of the control heights it moves.
double start_value(const ReflectorDesc& r, const std::string& name) {
    if (const auto it = r.parameters.find(name); it != r.parameters.end()) return it->second;
    const BSplineDesc& s = r.bspline;
    const auto g = s.groups.find(name);
    if (g == s.groups.end()) return 0.0;
    double sum = 0.0;
    int count = 0;
    for (int j = 0; j < s.ny; ++j)
        for (int i = 0; i < s.nx; ++i)
            if (in_control_group(g->second, i, j, s.nx, s.ny)) {
                sum += s.heights_mm[std::size_t(j) * s.nx + i];
                ++count;
            }
    return count ? sum / count : 0.0;
}

} // namespace

std::vector<std::pair<double, double>> ParameterSpace::bounds() const {
    std::vector<std::pair<double, double>> b;
    for (std::size_t k = 0; k < size(); ++k)
        b.emplace_back(lo[k], hi[k]);
    return b;
}

std::vector<std::uint64_t> ParameterSpace::lattice_counts() const {
    std::vector<std::uint64_t> counts;
    for (std::size_t k = 0; k < size(); ++k)
        // The tolerance keeps hi itself when (hi - lo) / step is whole but rounds below.
        counts.push_back(std::uint64_t(std::floor((hi[k] - lo[k]) / step[k] + 1e-9)) + 1);
    return counts;
}

std::uint64_t ParameterSpace::lattice_size() const {
    std::uint64_t n = 1;
    for (std::uint64_t c : lattice_counts())
        n = c != 0 && n > std::numeric_limits<std::uint64_t>::max() / c
                ? std::numeric_limits<std::uint64_t>::max()
                : n * c;
    return n;
}

std::vector<double> ParameterSpace::lattice_point(std::uint64_t index) const {
    const auto counts = lattice_counts();
    std::vector<double> x(size());
    for (std::size_t k = size(); k-- > 0;) {
        x[k] = lo[k] + double(index % counts[k]) * step[k];
        index /= counts[k];
    }
    return x;
}

std::vector<double> ParameterSpace::snap(const std::vector<double>& x) const {
    const auto counts = lattice_counts();
    std::vector<double> s(size());
    for (std::size_t k = 0; k < size(); ++k) {
        const double i =
            std::clamp(std::round((x[k] - lo[k]) / step[k]), 0.0, double(counts[k] - 1));
        s[k] = lo[k] + i * step[k];
    }
    return s;
}

std::map<std::string, double> ParameterSpace::named(const std::vector<double>& x) const {
    std::map<std::string, double> m;
    for (std::size_t k = 0; k < size(); ++k)
        m[names[k]] = x[k];
    return m;
}

std::string ParameterSpace::text(const std::vector<double>& x) const {
    std::string t;
    for (std::size_t k = 0; k < x.size() && k < size(); ++k)
        t += fmt::format("{}{}={:.6g}", k ? " " : "", names[k], x[k]);
    return t;
}

ReflectorDesc ParameterSpace::reflector(const ReflectorDesc& base,
                                        const std::vector<double>& x) const {
    ReflectorDesc r = base;
    for (std::size_t k = 0; k < size(); ++k)
        if (!is_source_parameter(names[k])) r.parameters[names[k]] = x[k];
    return r;
}

bool ParameterSpace::moves_source() const {
    return std::any_of(names.begin(), names.end(), is_source_parameter);
}

Scene ParameterSpace::candidate(const Scene& base, const std::vector<double>& x) const {
    Scene s = base;
    apply_design_parameters(s, named(x));
    return s;
}

ParameterSpace parameter_space(const Scene& scene) {
    const ReflectorDesc& r = scene.reflector;
    if (r.optimize.empty() && scene.source_optimize.empty())
        throw std::invalid_argument(fmt::format(
            "{}: [reflector.optimize] is missing: give bounds and a step for each parameter to "
            "search (e.g. fx = {{ min = 10.0, max = 20.0, step = 0.5 }}), or the source's in "
            "[source.optimize]",
            scene.path));
    ParameterSpace s;
    for (const auto& [name, range] : r.optimize) {
        s.names.push_back(name);
        s.lo.push_back(range.min);
        s.hi.push_back(range.max);
        s.step.push_back(range.step);
        s.start.push_back(std::clamp(start_value(r, name), range.min, range.max));
    }
    for (const auto& [key, range] : scene.source_optimize) {
        s.names.push_back(kSourceParameterPrefix + key);
        s.lo.push_back(range.min);
        s.hi.push_back(range.max);
        s.step.push_back(range.step);
        s.start.push_back(
            std::clamp(source_parameter_value(scene.source, key), range.min, range.max));
    }
    return s;
}

void refuse_start_outside_bounds(const Scene& scene) {
    const auto check = [&](const std::string& table, const std::string& name, double start,
                           const ParameterRange& range) {
        if (start < range.min || start > range.max)
            throw std::invalid_argument(fmt::format(
                "{}: [{}] {}: the start {:g} lies outside its bounds [{:g}, {:g}]; widen them or "
                "move the start",
                scene.path, table, name, start, range.min, range.max));
    };
    for (const auto& [name, range] : scene.reflector.optimize)
        check("reflector.optimize", name, start_value(scene.reflector, name), range);
    for (const auto& [key, range] : scene.source_optimize)
        check("source.optimize", key, source_parameter_value(scene.source, key), range);
}

namespace {

// Whether the reflector makes a surface clear of the source, and that surface.
Feasibility traceable(const Scene& scene, const ReflectorDesc& reflector,
                      std::optional<Surface>& surface) {
    Feasibility f;
    // A moved source stays over the holder's footprint, as a scene's must.
    const glm::dvec3& c = scene.source.center_mm;
    if (c.x < scene.holder.min_mm.x || c.x > scene.holder.max_mm.x || c.y < scene.holder.min_mm.y ||
        c.y > scene.holder.max_mm.y) {
        f.feasible = false;
        f.reason = fmt::format("the source at ({:.4g}, {:.4g}) mm is off the holder's footprint",
                               c.x, c.y);
        return f;
    }
    try {
        surface.emplace(Surface::make(reflector, scene.holder));
        f.clearance_mm = source_clearance_mm(*surface, scene.source);
    } catch (const std::invalid_argument& e) {
        f.feasible = false;
        f.clearance_mm = 0.0;
        f.reason = e.what();
        return f;
    }
    if (!(f.clearance_mm > 0.0)) {
        f.feasible = false;
        f.reason =
            fmt::format("the surface cuts the light source ({:.3g} mm deep)", -f.clearance_mm);
    }
    return f;
}

} // namespace

Feasibility traceable(const Scene& scene, const ReflectorDesc& reflector) {
    std::optional<Surface> surface;
    return traceable(scene, reflector, surface);
}

Feasibility candidate_feasibility(const Scene& scene, const ReflectorDesc& reflector) {
    std::optional<Surface> surface;
    Feasibility f = traceable(scene, reflector, surface);
    if (!f.feasible || !reflector.constraints.any()) return f;
    for (const ConstraintCheck& c : constraint_checks(*surface, reflector.constraints)) {
        if (c.met) continue;
        f.feasible = false;
        f.constraint = c.name;
        f.violation = c.violation;
        f.reason = fmt::format("[reflector.constraints] {}: the surface measures {:.4g}, beyond "
                               "the limit {:.4g}",
                               c.name, c.value, c.limit);
        break;
    }
    return f;
}

ReflectorDesc overridden(const Scene& scene, const std::map<std::string, double>& params) {
    ReflectorDesc r = scene.reflector;
    const auto names = family_parameters(r.family);
    for (const auto& [k, v] : params) {
        if (std::find(names.begin(), names.end(), k) == names.end() && !r.bspline.groups.count(k))
            throw std::invalid_argument(fmt::format("--parameters {}: not a parameter of the {} "
                                                    "family",
                                                    k, family_name(r.family)));
        r.parameters[k] = v;
    }
    const Feasibility f = traceable(scene, r);
    if (!f.feasible) throw std::invalid_argument("--parameters: " + f.reason);
    return r;
}

} // namespace fird
