// Candela tables and far-field histograms (DESIGN.md §2), both ways. The luminaire's
// photometric frame sits in the scene by a fixed rotation of 180 deg about x: nadir
// (gamma = 0) maps to +z, the reflector's opening; C0 maps to +x and C90 to -y. So a
// far-field cell (phi, theta) holds the directions C = -phi, gamma = 90 deg - theta.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "farfield/farfield.hpp"
#include "photometry/candela_table.hpp"

namespace fird {

// The scene direction of (C, gamma), degrees.
glm::dvec3 scene_direction(double c_deg, double gamma_deg);

// Lumens per far-field cell: the interpolated intensity integrated exactly over each
// cell's solid angle (cells split at the table's angles), so the histogram's total is
// integrated_flux_lm(table) up to rounding.
FarField farfield_from_table(const CandelaTable& table, std::uint32_t width, std::uint32_t height);

// A type C table on a regular grid (C every c_step_deg over [0, 360), gamma every
// gamma_step_deg over [0, 180]) from a far field: each node's candela is the lumens of
// the cells nearest to it over their solid angle; then one factor makes the table's
// flux equal the far field's total (reported in `flux_correction`). Throws
// std::invalid_argument when a step does not divide its range or is finer than the cells.
CandelaTable table_from_farfield(const FarField& farfield, double c_step_deg, double gamma_step_deg,
                                 double* flux_correction = nullptr);

} // namespace fird
