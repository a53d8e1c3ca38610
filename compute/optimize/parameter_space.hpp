// The box a search explores ([reflector.optimize]: bounds and a step per parameter), its
// lattice of steps (the paper's stepped search, §5), and the feasibility of a candidate.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "model/scene.hpp"

namespace fird {

struct ParameterSpace {
    // The optimized parameters: [reflector.optimize]'s (sorted by name), then
    // [source.optimize]'s, named "source.<key>" (design_parameters.hpp).
    std::vector<std::string> names;
    std::vector<double> lo, hi, step;
    std::vector<double> start; // the scene's reflector, clamped into the box

    std::size_t size() const { return names.size(); }
    // (lo, hi) per parameter.
    std::vector<std::pair<double, double>> bounds() const;
    // Lattice values per parameter: lo, lo + step, ... up to hi.
    std::vector<std::uint64_t> lattice_counts() const;
    // The product of the counts, saturating at UINT64_MAX.
    std::uint64_t lattice_size() const;
    // Lattice point `index` in odometer order: the last parameter varies fastest.
    std::vector<double> lattice_point(std::uint64_t index) const;
    // The nearest lattice point, coordinate by coordinate.
    std::vector<double> snap(const std::vector<double>& x) const;
    std::map<std::string, double> named(const std::vector<double>& x) const;
    // "name=value ..." in the names' order, for one-line messages.
    std::string text(const std::vector<double>& x) const;
    // The base reflector with x's reflector values.
    ReflectorDesc reflector(const ReflectorDesc& base, const std::vector<double>& x) const;
    // Whether some parameter moves the source (the candidates then do not share a rayset).
    bool moves_source() const;
    // The base scene with all of x's values: its reflector and its source.
    Scene candidate(const Scene& base, const std::vector<double>& x) const;
};

// Throws std::invalid_argument naming the scene when it has neither [reflector.optimize]
// nor [source.optimize].
ParameterSpace parameter_space(const Scene& scene);

// A search whose start lies outside a parameter's bounds is refused before any trace (one
// line naming the table and the parameter): parameter_space() would clamp it silently.
void refuse_start_outside_bounds(const Scene& scene);

struct Feasibility {
    bool feasible = true;
    double clearance_mm = 0.0; // source clearance (negative: how deep the surface cuts it)
    std::string reason;        // why not, in one line
    // The [reflector.constraints] key it breaks (empty: none), and by how much as a share
    // of its limit (the penalty grows with it, as with the clearance).
    std::string constraint;
    double violation = 0.0;
};

// A candidate is infeasible when its surface cuts the light source, its values make no
// surface (e.g. a zero focal length) or it breaks one of [reflector.constraints] (the
// press's limits, model/press_measures.hpp): it is then never traced (DESIGN.md §2).
Feasibility candidate_feasibility(const Scene& scene, const ReflectorDesc& reflector);
// The same without the press's constraints: whether the reflector can be traced at all (a
// surface clear of the source). An export, a screenshot or the search's start trace a
// reflector that breaks a constraint; only the search refuses it as a candidate.
Feasibility traceable(const Scene& scene, const ReflectorDesc& reflector);

// The scene's reflector with --parameters overrides (fird export); throws
// std::invalid_argument naming --parameters for a parameter the family lacks or values that
// make no traceable reflector.
ReflectorDesc overridden(const Scene& scene, const std::map<std::string, double>& params);

} // namespace fird
