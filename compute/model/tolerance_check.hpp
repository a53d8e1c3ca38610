// Whether a set of tolerances ([tolerance], issue 27 item 4) can be drawn for a source: one
// rule for the scene reader, fird tolerance's options and the workbench's tolerance form.
#pragma once

#include <optional>
#include <string>

#include "scene.hpp"

namespace fird {

struct ToleranceProblem {
    std::string key;    // the [tolerance] key at fault (its option: --key-with-dashes)
    std::string reason; // what is wrong with it, in a few words
};

// The first problem of `t` for `source`, or none: a surface error needs its correlation
// length; a tilt needs a source with an axis.
std::optional<ToleranceProblem> tolerance_problem(const ToleranceDesc& t, const SourceDesc& source);

} // namespace fird
