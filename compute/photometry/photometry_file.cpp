#include "photometry_file.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "photometry/ies_reader.hpp"
#include "photometry/ldt_reader.hpp"

namespace fird {

PhotometryFormat photometry_format(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".ies") return PhotometryFormat::Ies;
    if (ext == ".ldt") return PhotometryFormat::Ldt;
    throw std::invalid_argument(path + ": not a photometric file name (.ies or .ldt)");
}

CandelaTable read_photometry(const std::string& path) {
    return photometry_format(path) == PhotometryFormat::Ies ? read_ies(path) : read_ldt(path);
}

void write_photometry(const std::string& path, const CandelaTable& table,
                      const PhotometryLabels& labels) {
    if (photometry_format(path) == PhotometryFormat::Ies)
        write_ies(path, table, labels);
    else
        write_ldt(path, table, labels);
}

} // namespace fird
