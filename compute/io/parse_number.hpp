// A whole string as one finite number ("1e6", "-0.25"), or nothing: the one parse every
// reader of options, scripts and CSV files uses, each wrapping the error in its own words.
#pragma once

#include <cmath>
#include <exception>
#include <optional>
#include <string>

namespace fird {

inline std::optional<double> parse_finite_number(const std::string& text) {
    std::size_t used = 0;
    double v = 0.0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

} // namespace fird
