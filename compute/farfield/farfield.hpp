// The far-field histogram of DESIGN.md §2: lumens per (azimuth, altitude) cell, and the
// l2 distance between two of them.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace fird {

struct FarField {
    std::uint32_t width = 0;  // azimuth cells, phi in [-pi, pi)
    std::uint32_t height = 0; // altitude cells, row 0 the zenith (+z)
    std::vector<double> lm;   // row-major, height rows of width cells
    double total_lm() const;
};

// Cell index (row * width + column) of a unit direction:
// column = floor((phi + pi) / 2pi * W), row = floor((pi/2 - theta) / pi * H), clamped.
std::uint32_t farfield_cell(const glm::dvec3& direction, std::uint32_t width, std::uint32_t height);

FarField farfield_from_counts(const std::vector<std::uint64_t>& counts, std::uint32_t width,
                              std::uint32_t height, double lm_per_ray);

// sqrt(sum (a_i - b_i)^2) in lumens; throws std::invalid_argument when grids differ.
double l2_distance(const FarField& a, const FarField& b);

// How two far fields are compared ([optimize] metric). L2: the paper's, over lumens per
// cell, where a cell at the pole (the luminaire's axis) covers ~570x less solid angle than
// one at the equator, so an error on the axis counts for almost nothing. CandelaL2: over
// intensities, each cell weighted by its solid angle, as an RMS over the sphere:
// sqrt(sum_i omega_i (I_i - J_i)^2 / 4 pi) in cd, I = lm / omega, which is
// sqrt(sum_i (a_i - b_i)^2 w_i) with w_i = 1 / (4 pi omega_i).
enum class FarFieldMetric { L2, CandelaL2 };
const char* metric_name(FarFieldMetric metric); // "l2", "candela_l2"
const char* metric_unit(FarFieldMetric metric); // "lm", "cd"

// w_i of `metric` for the cells of row `row` (1 for L2).
double metric_cell_weight(FarFieldMetric metric, std::uint32_t row, std::uint32_t width,
                          std::uint32_t height);

// sqrt(sum_i w_i (a_i - b_i)^2): l2_distance for L2.
double farfield_distance(const FarField& a, const FarField& b, FarFieldMetric metric);

// The Monte Carlo noise of independent rays (the `random` sampler), per ray: a far field
// binned from n independent rays of equal energy is multinomial over its cells, so its
// squared l2 to its own expectation has the mean flux^2 sum_i p_i (1 - p_i) / n, p_i the
// share of the flux in cell i (taken from `expected`). Returns flux^2 sum p (1 - p) in lm^2:
// divide by the rays. A stratified sampler is quieter (its noise must be measured).
// With a metric, the same with each cell's term weighted by its w_i (the expectation of
// the metric's squared distance instead of l2's).
double multinomial_noise_lm2_times_rays(const FarField& expected, double flux_lm,
                                        FarFieldMetric metric = FarFieldMetric::L2);

// The same light on a coarser grid whose cells are blocks of the finer one's: width and
// height must divide the far field's (binning is additive, so this equals binning the
// rays on the coarse grid). Throws std::invalid_argument otherwise.
FarField coarsen_farfield(const FarField& farfield, std::uint32_t width, std::uint32_t height);

// The solid angle of one cell of row `row` of a width x height grid, in steradians.
double farfield_cell_solid_angle_sr(std::uint32_t row, std::uint32_t width, std::uint32_t height);

// The direction at the centre of a cell (for tests and conversions).
glm::dvec3 farfield_cell_direction(std::uint32_t column, std::uint32_t row, std::uint32_t width,
                                   std::uint32_t height);

} // namespace fird
