// What `fird photometry info` and `fird photometry convert` do (the app only wires).
#pragma once

#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "photometry/candela_table.hpp"

namespace fird {

// format, version, photometric_type, symmetry, n_vertical, n_horizontal,
// flux_declared_lm (null when the file gives none), flux_integrated_lm, peak_cd.
nlohmann::json photometry_info_json(const CandelaTable& table);

struct ConvertOptions {
    double c_step_deg = 5.0; // grids of a table made from a far field (.npy input)
    double gamma_step_deg = 1.0;
    std::uint32_t farfield_w = 1800; // far field written to .npy
    std::uint32_t farfield_h = 900;
};

// IN: .ies, .ldt or a far-field .npy (lumens, DESIGN.md §2); OUT: .ies, .ldt, .npy
// (the far field by cell integration) or .png (polar plot). Throws with a one-line
// message naming the file.
void convert_photometry(const std::string& in, const std::string& out,
                        const ConvertOptions& options);

} // namespace fird
