// What a lighting engineer reads off a luminaire beside its equirectangular far field, as
// data the pictures (plot/luminaire_pictures.hpp) draw and the tests check: isocandela
// lines in C-gamma, the illuminance on a plane across the beam at a given distance, and
// how far from nadir the light reaches. All from a type C candela table
// (table_from_farfield: nadir, gamma 0, is the reflector's opening, +z in the scene).
#pragma once

#include <vector>

#include "photometry/candela_table.hpp"

namespace fird {

// The gamma (degrees) within which `share` of the table's flux leaves (0..180), from the
// zonal flux of its interpolated intensity.
double gamma_holding_deg(const CandelaTable& table, double share);

// A segment of an isocandela line, its ends in (C, gamma) degrees.
struct IsoSegment {
    double level_cd;
    double c0_deg, gamma0_deg, c1_deg, gamma1_deg;
};

// The lines where the interpolated intensity equals each level, for gamma in
// [0, gamma_max_deg]: marching squares on a grid of `c_step_deg` x `gamma_step_deg`
// (crossings linear between nodes; a saddle cell joined by the mean of its corners). C runs
// over [0, 360]: a line that crosses C = 0 is cut there. Throws std::invalid_argument for a
// step not above 0 or a gamma range that is not finite (clamped to 0..180).
std::vector<IsoSegment> isocandela_segments(const CandelaTable& table,
                                            const std::vector<double>& levels_cd,
                                            double gamma_max_deg, double c_step_deg = 1.0,
                                            double gamma_step_deg = 0.5);

// The illuminance (lux) on a plane square to nadir at `distance_m` below the luminaire,
// sampled at n x n points over [-half_width_m, half_width_m]^2: E = I(C, gamma) cos^3 gamma
// / d^2 (the inverse square law on a tilted patch), with gamma = atan(r / d) and C the
// point's azimuth from x (along C0) towards y (along C90). Row 0 at y = -half_width_m.
// Throws std::invalid_argument unless the distance is finite and > 0 and the half width
// finite and >= 0.
struct IlluminanceMap {
    int samples = 0;
    double distance_m = 0.0, half_width_m = 0.0;
    std::vector<double> lux; // samples x samples, row-major
    double at(int ix, int iy) const { return lux[std::size_t(iy) * samples + ix]; }
    double position_m(int i) const {
        return samples > 1 ? -half_width_m + 2.0 * half_width_m * i / (samples - 1) : 0.0;
    }
};
IlluminanceMap illuminance_on_plane(const CandelaTable& table, double distance_m,
                                    double half_width_m, int samples);

// The illuminance (lux) at one point (x_m, y_m) of that plane, and the direction (C, gamma
// in degrees) the light reaching it leaves in: the map's formula at that point.
struct PlanePoint {
    double lux, c_deg, gamma_deg;
};
PlanePoint illuminance_at(const CandelaTable& table, double distance_m, double x_m, double y_m);

} // namespace fird
