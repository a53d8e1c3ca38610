// NumPy .npy files (format versions 1.0 and 2.0): little-endian C-order arrays.
#pragma once

#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace fird {

// Writes `values` (rows x cols, row-major) as float32; throws on I/O errors.
void write_npy_f32(const std::string& path, const std::vector<double>& values, std::uint32_t rows,
                   std::uint32_t cols);

// What an .npy file's header says: the element type (float32 or float64), the shape and
// the byte offset at which the data begins.
struct NpyHeader {
    bool float64 = false;
    std::vector<std::uint64_t> shape;
    std::uint64_t data_offset = 0;
};
// Reads the header of a little-endian float32 or float64 C-order array from the start of
// `in`; throws with the file name and the byte offset on anything else.
NpyHeader read_npy_header(std::istream& in, const std::string& path);

struct NpyArray {
    std::vector<std::uint64_t> shape;
    std::vector<float> values;
};
// Reads a float32 C-order .npy; throws with the file name on anything else.
NpyArray read_npy_f32(const std::string& path);

} // namespace fird
