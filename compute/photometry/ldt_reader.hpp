// EULUMDAT (.ldt) into a candela table.
#pragma once

#include <string>
#include <string_view>

#include "candela_table.hpp"

namespace fird {

// Throws PhotometryError naming the file and line.
CandelaTable read_ldt(const std::string& path);
CandelaTable read_ldt_bytes(const std::string& path, std::string_view bytes);

} // namespace fird
