// Option values the commands share: counts written as 1e6, comma lists, k=v lists. A bad
// value is a UsageError naming the option (exit code 2).
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

namespace fird::app {

struct UsageError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

std::vector<std::string> split_list(const std::string& text, char separator = ',');

// A whole number >= 1 and <= max, written plainly or as 1e6; errors name the option.
std::uint64_t parse_count(const std::string& option, const std::string& text, double max = 1e10);
std::vector<std::uint64_t> parse_counts(const std::string& option, const std::string& text,
                                        double max = 1e10);

// WxH in whole pixels, each side in [min_px, max_px]; errors name the option.
std::pair<std::uint32_t, std::uint32_t> parse_size(const std::string& option,
                                                   const std::string& text, std::uint32_t min_px,
                                                   std::uint32_t max_px);

// A check for a number option: finite and within [lo, hi] (CLI::Range lets NaN through).
CLI::Validator finite_range(double lo, double hi);

// NAME=VALUE,NAME=VALUE with finite numbers.
std::map<std::string, double> parse_assignments(const std::string& option, const std::string& text);

} // namespace fird::app
