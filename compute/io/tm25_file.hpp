// IES TM-25-13 binary ray files: what the header says about the rays that follow it (their
// count, their columns, where they begin) and the source's flux. Little-endian throughout.
#pragma once

#include <array>
#include <cstdint>
#include <istream>
#include <string>

namespace fird {

struct Tm25Header {
    std::uint64_t rays = 0;
    // The header's totals; NaN where the file leaves them unknown (NaN or 0 in the file).
    double luminous_flux_lm = 0.0;
    double radiant_flux_w = 0.0;
    // The known-data flags (4.7.2): position, direction, radiant flux, wavelength,
    // luminous flux, Stokes parameters, tristimulus values, spectrum index.
    std::array<bool, 8> flags{};
    std::uint32_t columns = 0;       // floats per ray record
    int radiant_column = -1;         // W per ray, where flagged
    int luminous_column = -1;        // lm per ray, where flagged
    std::uint64_t ray_offset = 0;    // the byte at which ray 0 begins
    std::array<std::string, 9> text; // the description fields (4.7.3), as UTF-8
    // Quirks of published files, read rather than refused:
    bool padding_missing = false;  // the spectral tables' padding to 32 bytes left out
    bool flux_nan_swapped = false; // a NaN flux written big-endian (a denormal read here)
};

// Reads and checks the header of a file of `file_bytes` bytes. Refusals throw
// std::runtime_error "PATH: byte N: what" (a short file, a bad tag or version, a flag other
// than 0 or 1, a negative flux, a ray count that disagrees with the file's size).
Tm25Header read_tm25_header(std::istream& in, std::uint64_t file_bytes, const std::string& path);

} // namespace fird
