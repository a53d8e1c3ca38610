#include "parse.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "io/parse_number.hpp"

namespace fird::app {

namespace {
double number(const std::string& option, const std::string& text) {
    const auto v = parse_finite_number(text);
    if (!v) throw UsageError(fmt::format("{}: '{}' is not a number", option, text));
    return *v;
}
} // namespace

CLI::Validator finite_range(double lo, double hi) {
    return CLI::Validator(
        [lo, hi](std::string& text) -> std::string {
            const auto v = parse_finite_number(text);
            if (!v) return fmt::format("'{}' is not a finite number", text);
            if (!(*v >= lo && *v <= hi))
                return fmt::format("{} is not in [{:g}, {:g}]", text, lo, hi);
            return {};
        },
        fmt::format("FINITE in [{:g} - {:g}]", lo, hi));
}

std::vector<std::string> split_list(const std::string& text, char separator) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, separator);)
        if (!item.empty()) out.push_back(item);
    return out;
}

std::uint64_t parse_count(const std::string& option, const std::string& text, double max) {
    const double v = number(option, text);
    if (!(v >= 1.0 && v <= max) || v != std::floor(v))
        throw UsageError(
            fmt::format("{}: {} must be a whole number between 1 and {:g}", option, text, max));
    return std::uint64_t(v);
}

std::vector<std::uint64_t> parse_counts(const std::string& option, const std::string& text,
                                        double max) {
    std::vector<std::uint64_t> out;
    for (const auto& item : split_list(text))
        out.push_back(parse_count(option, item, max));
    if (out.empty()) throw UsageError(fmt::format("{}: no value given", option));
    return out;
}

std::pair<std::uint32_t, std::uint32_t> parse_size(const std::string& option,
                                                   const std::string& text, std::uint32_t min_px,
                                                   std::uint32_t max_px) {
    const auto x = text.find('x');
    if (x == std::string::npos) throw UsageError(fmt::format("{} {}: not WxH", option, text));
    const auto w = parse_count(option, text.substr(0, x), max_px);
    const auto h = parse_count(option, text.substr(x + 1), max_px);
    if (w < min_px || h < min_px)
        throw UsageError(fmt::format("{} {}: at least {}x{}", option, text, min_px, min_px));
    return {std::uint32_t(w), std::uint32_t(h)};
}

std::map<std::string, double> parse_assignments(const std::string& option,
                                                const std::string& text) {
    std::map<std::string, double> out;
    for (const auto& item : split_list(text)) {
        const auto eq = item.find('=');
        if (eq == std::string::npos || eq == 0)
            throw UsageError(fmt::format("{}: '{}' is not NAME=VALUE", option, item));
        out[item.substr(0, eq)] = number(option, item.substr(eq + 1));
    }
    return out;
}

} // namespace fird::app
