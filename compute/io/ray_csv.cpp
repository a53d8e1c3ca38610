#include "ray_csv.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "io/parse_number.hpp"

namespace fird {

namespace {

constexpr std::array<const char*, 6> kNames = {"x", "y", "z", "dx", "dy", "dz"};

std::string_view trimmed(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
        s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> fields(std::string_view line) {
    std::vector<std::string_view> out;
    for (;;) {
        const std::size_t comma = line.find(',');
        out.push_back(trimmed(line.substr(0, comma)));
        if (comma == std::string_view::npos) return out;
        line.remove_prefix(comma + 1);
    }
}

} // namespace

CsvRayColumns csv_ray_columns(std::string_view header, const std::string& path) {
    CsvRayColumns c;
    c.position_direction.fill(-1);
    const std::vector<std::string_view> names = fields(header);
    c.count = int(names.size());
    for (std::size_t k = 0; k < names.size(); ++k) {
        std::string name(names[k]);
        std::transform(name.begin(), name.end(), name.begin(),
                       [](unsigned char ch) { return char(std::tolower(ch)); });
        for (std::size_t j = 0; j < kNames.size(); ++j)
            if (name == kNames[j]) c.position_direction[j] = int(k);
        if (name == "flux") c.flux = int(k);
    }
    for (std::size_t j = 0; j < kNames.size(); ++j)
        if (c.position_direction[j] < 0)
            throw std::runtime_error(fmt::format(
                "{}: line 1: no column '{}' (the header names x, y, z, dx, dy, dz[, flux])", path,
                kNames[j]));
    return c;
}

std::array<double, 7> parse_csv_ray(std::string_view line, const CsvRayColumns& columns,
                                    const std::string& path, std::uint64_t line_number) {
    const std::vector<std::string_view> f = fields(line);
    if (int(f.size()) != columns.count)
        throw std::runtime_error(fmt::format("{}: line {}: {} columns, the header names {}", path,
                                             line_number, f.size(), columns.count));
    std::array<double, 7> v{0, 0, 0, 0, 0, 0, 1.0};
    const auto value = [&](int column, const char* name) {
        const std::optional<double> x = parse_finite_number(std::string(f[std::size_t(column)]));
        if (!x)
            throw std::runtime_error(fmt::format("{}: line {}: {} '{}' is not a finite number",
                                                 path, line_number, name, f[std::size_t(column)]));
        return *x;
    };
    for (std::size_t j = 0; j < kNames.size(); ++j)
        v[j] = value(columns.position_direction[j], kNames[j]);
    if (columns.flux >= 0) v[6] = value(columns.flux, "flux");
    return v;
}

} // namespace fird
