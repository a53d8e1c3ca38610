#include "tolerance_check.hpp"

#include <fmt/format.h>

#include "source.hpp"

namespace fird {

std::optional<ToleranceProblem> tolerance_problem(const ToleranceDesc& t,
                                                  const SourceDesc& source) {
    if (t.realisations == 0) return ToleranceProblem{"realisations", "at least one is needed"};
    if (t.surface_rms_mm > 0.0 && !(t.surface_correlation_mm > 0.0))
        return ToleranceProblem{
            "surface_correlation_mm",
            "must be > 0 where a surface error is given (the error's correlation length)"};
    if (t.source_tilt_deg > 0.0 && !source_has_axis(source))
        return ToleranceProblem{"source_tilt_deg", fmt::format("a {} source has no axis to tilt",
                                                               source_type_name(source.kind))};
    return std::nullopt;
}

} // namespace fird
