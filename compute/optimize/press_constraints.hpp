// The press's constraints ([reflector.constraints]) as the search sees them beyond each
// candidate's feasibility (parameter_space.hpp): a limit no candidate in the box can meet
// is refused before any trace, and at the optimum each limit is reported met or not and
// active or not (a candidate one step away breaks it: the limit, not the light, holds the
// optimum there).
#pragma once

#include <string>
#include <vector>

#include "model/scene.hpp"
#include "optimize/parameter_space.hpp"

namespace fird {

// Above this many free parameters the box's 2^n corners are too many to measure: the
// refusal then looks at each parameter's two ends alone (the others at the start).
constexpr std::size_t kCornersUpTo = 8;

// Throws std::invalid_argument naming [reflector.constraints] and the key when every
// candidate looked at breaks it: the start, the box's centre and its corners (up to
// kCornersUpTo parameters; beyond, each parameter's ends). A cheap look, not a proof: a
// limit met only strictly inside the box, away from all of those, is refused too, and the
// message says where the measure came closest so the limit or the box can be moved.
void refuse_unmeetable_constraints(const Scene& scene, const ParameterSpace& space);

struct ConstraintAtOptimum {
    std::string name; // the scene key
    double value = 0.0;
    double limit = 0.0;
    bool met = true;
    bool active = false;   // a candidate one step away (one parameter) breaks it
    std::string active_by; // which: "fx + 1 step"
};
// Every constraint given, at x (the search's best).
std::vector<ConstraintAtOptimum> constraints_at(const Scene& scene, const ParameterSpace& space,
                                                const std::vector<double>& x);

} // namespace fird
