// CSV ray sets: a header line naming the columns x, y, z, dx, dy, dz and optionally flux
// (in any order, among others), then one ray per line.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

namespace fird {

struct CsvRayColumns {
    std::array<int, 6> position_direction{}; // the columns of x, y, z, dx, dy, dz
    int flux = -1;                           // the flux column, or -1
    int count = 0;                           // columns in all
};

// The columns named by a header line (names trimmed, case-insensitive); throws
// std::runtime_error "PATH: line 1: what" where one of x, y, z, dx, dy, dz is missing.
CsvRayColumns csv_ray_columns(std::string_view header, const std::string& path);

// One ray's line: its 7 values (the flux 1 where there is no flux column). Throws
// std::runtime_error "PATH: line N: what" on a missing or malformed number.
std::array<double, 7> parse_csv_ray(std::string_view line, const CsvRayColumns& columns,
                                    const std::string& path, std::uint64_t line_number);

} // namespace fird
