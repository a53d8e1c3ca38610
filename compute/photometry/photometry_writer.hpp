// IES LM-63-2002 and EULUMDAT writers for a type C candela table (a far field turned
// into a table, or a file read in: conversion between the formats).
#pragma once

#include <string>

#include "photometry/candela_table.hpp"

namespace fird {

struct PhotometryLabels {
    std::string luminaire = "FIRD reflector"; // [LUMINAIRE] / luminaire name
    std::string test = "FIRD far field";      // [TEST] / measurement report
    std::string other;                        // [OTHER] / date-user line (e.g. the scene)
};

// Absolute photometry (lumens = -1, multiplier 1), all C planes 0..360 (symmetry none),
// ten numbers per line. Throws std::runtime_error naming the path on failure.
void write_ies(const std::string& path, const CandelaTable& table, const PhotometryLabels& labels);

// Isym 0, one lamp set whose flux is the table's integrated flux, LORL 100 %, intensities
// in cd/klm of that flux (so a reader recovers the candela exactly).
void write_ldt(const std::string& path, const CandelaTable& table, const PhotometryLabels& labels);

} // namespace fird
