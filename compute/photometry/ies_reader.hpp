// IES LM-63 (1986, 1991, 1995, 2002, 2019) into a candela table.
#pragma once

#include <string>
#include <string_view>

#include "candela_table.hpp"

namespace fird {

// Reads an IES file; TILT=<file> is read relative to it. Throws PhotometryError naming
// the file and line.
CandelaTable read_ies(const std::string& path);
// The same from bytes (fuzzing, tests); TILT=<file> is resolved against `path`'s folder.
CandelaTable read_ies_bytes(const std::string& path, std::string_view bytes);

} // namespace fird
