// The far field as a false-colour PNG with a colour bar and angle labels, laid out as
// the paper's figures: azimuth across (-180..180 deg), altitude down (+90 at the top).
#pragma once

#include <string>

#include "farfield/farfield.hpp"

namespace fird {

struct FarFieldImageOptions {
    std::string title;
    bool signed_values = false; // a difference image: diverging colours around 0
};

void write_farfield_png(const std::string& path, const FarField& farfield,
                        const FarFieldImageOptions& options);

} // namespace fird
