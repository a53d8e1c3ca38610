// Photometric files by their extension: .ies (IES LM-63) or .ldt (EULUMDAT).
#pragma once

#include <string>

#include "photometry/candela_table.hpp"
#include "photometry/photometry_writer.hpp"

namespace fird {

enum class PhotometryFormat { Ies, Ldt };

// From the extension (case-insensitive); throws std::invalid_argument naming the path.
PhotometryFormat photometry_format(const std::string& path);

CandelaTable read_photometry(const std::string& path);
void write_photometry(const std::string& path, const CandelaTable& table,
                      const PhotometryLabels& labels);

} // namespace fird
