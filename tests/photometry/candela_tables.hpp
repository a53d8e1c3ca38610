// Candela tables built in a test from a formula, for the photometry tests' closed forms.
#pragma once

#include <cstddef>
#include <vector>

#include "photometry/candela_table.hpp"

namespace fird::test {

// A type C table of planes `planes_deg` (each constant in C between them, as
// intensity_cd interpolates) with intensity cd(c index, gamma) every degree of gamma.
template <class Cd>
CandelaTable formula_table(const std::vector<double>& planes_deg, const Cd& cd) {
    CandelaTable t;
    t.c_deg = planes_deg;
    for (int g = 0; g <= 180; ++g)
        t.gamma_deg.push_back(g);
    for (std::size_t c = 0; c < planes_deg.size(); ++c)
        for (int g = 0; g <= 180; ++g)
            t.cd.push_back(cd(c, double(g)));
    return t;
}

} // namespace fird::test
