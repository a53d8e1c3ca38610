// NumPy .npy files (format version 1.0): float32 arrays, little-endian, C order.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fird {

// Writes `values` (rows x cols, row-major) as float32; throws on I/O errors.
void write_npy_f32(const std::string& path, const std::vector<double>& values, std::uint32_t rows,
                   std::uint32_t cols);

struct NpyArray {
    std::vector<std::uint64_t> shape;
    std::vector<float> values;
};
// Reads a float32 C-order .npy; throws with the file name on anything else.
NpyArray read_npy_f32(const std::string& path);

} // namespace fird
