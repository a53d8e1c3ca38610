// IES LM-63-2019 and EULUMDAT writers for a type C candela table (a far field turned
// into a table, or a file read in: conversion between the formats), in absolute candela.
#pragma once

#include <string>

#include "photometry/candela_table.hpp"

namespace fird {

struct PhotometryLabels {
    std::string luminaire = "FIRD reflector"; // [LUMINAIRE] / luminaire name
    std::string test = "FIRD far field";      // [TEST] / measurement report
    std::string other;                        // [OTHER] / date-user line (e.g. the scene)
    // The light source's flux (the luminaire's lamp): EULUMDAT's lamp flux, of which the
    // table's flux is the light output ratio, and LM-63's [LAMP]. 0: the table's own flux
    // (LORL 100 %), for a file converted from another.
    double lamp_flux_lm = 0.0;
    // LM-63-2019's file generation type: a ray-traced far field is a simulation (1.00010);
    // otherwise undefined (1.00001).
    bool simulated = false;
    std::string issue_date; // [ISSUEDATE] / EULUMDAT's date line; empty: today (UTC)
};

// LM-63-2019 with its required keywords ([TEST], [TESTLAB], [ISSUEDATE], [MANUFAC]) and the
// file generation type; absolute photometry (lumens = -1, multiplier 1), all C planes
// 0..360 (symmetry none), ten numbers per line. Throws std::runtime_error naming the path.
void write_ies(const std::string& path, const CandelaTable& table, const PhotometryLabels& labels);

// Isym 0, one lamp set of the source's flux (labels.lamp_flux_lm, else the table's), the
// light output ratio LORL = the table's flux / the lamp's, intensities in cd/klm of the
// lamp's flux (so a reader recovers the candela, and the luminaire's flux, exactly).
void write_ldt(const std::string& path, const CandelaTable& table, const PhotometryLabels& labels);

} // namespace fird
