// The beam of a far field as a luminaire's data sheet states it: the peak intensity and the
// beam angle about the zenith (the reflector's opening, the luminaire's axis).
#pragma once

#include "farfield/farfield.hpp"

namespace fird {

struct BeamMetrics {
    // The largest intensity over patches of about 1 degree of gamma by 5 of C (whole cells;
    // a cap of whole rows at each pole), a luminaire file's resolution. Not the largest
    // cell's: the cells about the zenith are so small that a few rays there would read as
    // an enormous intensity.
    double peak_cd = 0.0;
    // The full angle of the cone about the zenith out to the last polar angle where the
    // azimuth-averaged intensity is at least half its largest value (linear between rows;
    // for a batwing, its outer half-maximum edge).
    double beam_angle_deg = 0.0;
};

BeamMetrics beam_metrics(const FarField& farfield);

} // namespace fird
