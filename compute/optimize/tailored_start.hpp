// A start from the target (fird optimize --start tailored, issue 26 item 5): the profile
// that a point source at the source's centre would need to make the desired far field,
// by the flux-mapping ("tailoring") method of nonimaging optics (Elmer, "The Optical
// Design of Reflectors"; Ries and Winston, "Tailored edge-ray reflectors for illumination",
// JOSA A 11, 1994). Meridional: the source and the target are averaged over azimuth about
// the reflector's axis, so every ray stays in its meridional plane. Pure computation (no
// device); optimize/search_start.hpp applies it to a scene.
#pragma once

#include <cstdint>
#include <vector>

#include "farfield/farfield.hpp"
#include "model/scene.hpp"

namespace fird {

// Flux over polar bands of equal width on [0, pi], accumulated: the flux within an angle,
// linear inside a band (the band's flux spread evenly over its width).
struct PolarCdf {
    std::vector<double> cumulative_lm; // at the band edges k pi / bands, k = 0 .. bands
    double total_lm() const { return cumulative_lm.back(); }
    double at(double angle_rad) const; // flux within [0, angle]
    // The least angle within which `flux_lm` lies (0 .. total; clamped).
    double inverse(double flux_lm) const;
};
PolarCdf polar_cdf(const std::vector<double>& band_lm);

// The source's flux per polar band about the downward axis (-z, towards the reflector's
// apex), from `rays` of its emission law (directions only: the source as a point).
std::vector<double> source_nadir_bands_lm(const SourceDesc& source, std::uint64_t rays,
                                          std::uint32_t bands);
// The far field's flux per polar band about the upward axis (+z): its rows summed over
// azimuth (row j covers the polar angles j pi / H .. (j + 1) pi / H from the zenith).
std::vector<double> farfield_zenith_bands_lm(const FarField& farfield);

// Which way a reflected ray leaves its meridional plane's half: away from the axis (the
// target's cone [0, gamma] filled by rays that diverge) or across it (rays that cross the
// axis, the "crossed" edge-ray design). Both send the axis ray straight up (a smooth apex).
enum class EdgeRay { Diverging, Crossing };
const char* edge_ray_name(EdgeRay edge);

struct TailoringProblem {
    std::vector<double> source_band_lm; // source_nadir_bands_lm
    std::vector<double> target_band_lm; // farfield_zenith_bands_lm
    double apex_depth_mm = 0.0;         // the apex's distance below the source point (> 0)
    double radius_mm = 0.0;             // the profile's radius: the reflector's rim
    int heights = 0;                    // the profile's heights, at r_k = k radius / (n - 1)
    EdgeRay edge = EdgeRay::Crossing;
};

struct TailoredProfile {
    // The curve's depth below the source point (negative: below) at the profile's radii.
    std::vector<double> z_mm;
    double rim_polar_rad = 0.0;         // the source angle from the nadir that meets the rim
    bool reaches_rim = true;            // false: the curve rose to the source's level first
    double source_share = 0.0;          // the share of the source's flux within the rim's cone
    double target_share_left_out = 0.0; // the target's share below the horizon (not mapped)
    // The flux map: source angle theta (from the nadir) to far-field angle gamma (from the
    // zenith), sampled along the curve, with the curve itself (r, z below the source).
    std::vector<double> theta_rad, gamma_rad, r_mm, curve_z_mm;
};

// Solves the meridional tailoring problem: gamma(theta) holds the same share of the
// target's flux above the horizon as theta of the source's (within the rim's cone), and the mirror
// curve follows d(ln rho)/d(theta) = tan((theta +- gamma) / 2) from the apex. Throws
// std::invalid_argument with one line when it has no answer (no light, or a curve that
// turns back on itself or runs off to infinity).
TailoredProfile tailor_profile(const TailoringProblem& problem);

} // namespace fird
