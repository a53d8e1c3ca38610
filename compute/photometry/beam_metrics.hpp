// The beam of a far field as a luminaire's data sheet states it: the peak intensity and the
// beam angle about the zenith (the reflector's opening, the luminaire's axis).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "farfield/farfield.hpp"

namespace fird {

struct BeamMetrics {
    // The largest intensity over patches of about 1 degree of gamma by 5 of C (whole cells;
    // a cap of whole rows at each pole), a luminaire file's resolution. Not the largest
    // cell's: the cells about the zenith are so small that a few rays there would read as
    // an enormous intensity.
    double peak_cd = 0.0;
    // The full angle of the cone about the zenith out to the last polar angle where the
    // azimuth-averaged intensity, over bands of about 1 degree, is at least half its
    // largest value (linear between band centres; for a batwing, its outer edge).
    double beam_angle_deg = 0.0;
};

BeamMetrics beam_metrics(const FarField& farfield);

// An angle in each of a data sheet's two planes: C0-C180 and C90-C270.
struct PlaneAngles {
    double c0_deg = 0.0;
    double c90_deg = 0.0;
};

// What a luminaire's data sheet states of a far field (issue 26's photometrics), in the
// photometric frame of photometry/farfield_photometry.hpp (gamma = 0 along +z).
struct Photometrics {
    double efficiency = 0.0; // the far field's flux over the source's
    double peak_cd = 0.0;    // BeamMetrics::peak_cd
    double peak_c_deg = 0.0; // the peak patch's centre
    double peak_gamma_deg = 0.0;
    // In each plane, the angle between its outermost directions where the intensity is 50 %
    // (beam) or 10 % (field) of the plane's own peak (a data sheet's convention: the
    // luminaire's peak may lie off both planes, and a share of it would make a plane's angle
    // jump between 0 and its width as noise moves the plane's top across it), over the same
    // patches as the peak (about 1 degree of gamma by 5 of C about the plane; a cap of whole
    // rows at the poles), linear between patch centres. 0 for a plane without light.
    PlaneAngles beam_angle_deg;
    PlaneAngles field_angle_deg;
};

Photometrics photometrics(const FarField& farfield, double source_flux_lm);

// {"efficiency", "peak_cd", "peak_direction_deg": [C, gamma], "beam_angle_deg":
// {"C0", "C90"}, "field_angle_deg": {"C0", "C90"}}
nlohmann::json photometrics_json(const Photometrics& photometrics);
// One line of text from photometrics_json's object (read by key).
std::string photometrics_text(const nlohmann::json& photometrics);

} // namespace fird
