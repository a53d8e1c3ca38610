#include "npy.hpp"

#include <cstring>
#include <fstream>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fird {

void write_npy_f32(const std::string& path, const std::vector<double>& values, std::uint32_t rows,
                   std::uint32_t cols) {
    if (values.size() != std::size_t(rows) * cols)
        throw std::invalid_argument("write_npy_f32: shape does not match the data");
    std::string header =
        fmt::format("{{'descr': '<f4', 'fortran_order': False, 'shape': ({}, {}), }}", rows, cols);
    // Magic (6) + version (2) + length (2) + header + '\n' is a multiple of 64.
    const std::size_t unpadded = 10 + header.size() + 1;
    header.append((64 - unpadded % 64) % 64, ' ');
    header.push_back('\n');
    write_atomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
        const std::uint16_t length = std::uint16_t(header.size());
        out.write("\x93NUMPY\x01\x00", 8);
        out.put(char(length & 0xff));
        out.put(char(length >> 8));
        out.write(header.data(), std::streamsize(header.size()));
        std::vector<float> f(values.begin(), values.end());
        out.write(reinterpret_cast<const char*>(f.data()),
                  std::streamsize(f.size() * sizeof(float)));
        out.close();
        if (!out) throw std::runtime_error(fmt::format("{}: write failed", path));
    });
}

NpyHeader read_npy_header(std::istream& in, const std::string& path) {
    char magic[10];
    in.read(magic, 10);
    if (!in || std::memcmp(magic, "\x93NUMPY", 6) != 0 || (magic[6] != 1 && magic[6] != 2))
        throw std::runtime_error(fmt::format("{}: byte 0: not a version 1 or 2 .npy file", path));
    // Version 1 gives the header's length in 2 bytes, version 2 in 4.
    std::size_t length = std::uint8_t(magic[8]) | (std::size_t(std::uint8_t(magic[9])) << 8);
    std::uint64_t at = 10;
    if (magic[6] == 2) {
        char more[2];
        in.read(more, 2);
        if (!in) throw std::runtime_error(fmt::format("{}: byte 10: short file", path));
        length |=
            (std::size_t(std::uint8_t(more[0])) << 16) | (std::size_t(std::uint8_t(more[1])) << 24);
        at = 12;
    }
    if (length > (1u << 20))
        throw std::runtime_error(fmt::format("{}: byte 8: a header of {} bytes", path, length));
    std::string header(length, '\0');
    in.read(header.data(), std::streamsize(length));
    if (!in) throw std::runtime_error(fmt::format("{}: byte {}: short file", path, at));
    NpyHeader h;
    h.data_offset = at + length;
    const bool f4 = header.find("'<f4'") != std::string::npos;
    const bool f8 = header.find("'<f8'") != std::string::npos;
    if ((!f4 && !f8) || header.find("False") == std::string::npos)
        throw std::runtime_error(fmt::format(
            "{}: byte {}: not a little-endian float32 or float64 C-order array", path, at));
    h.float64 = f8;
    std::smatch m;
    if (!std::regex_search(header, m, std::regex(R"(\(([0-9, ]*)\))")))
        throw std::runtime_error(fmt::format("{}: byte {}: no shape in the header", path, at));
    const std::string dims = m[1];
    const std::regex number("[0-9]+");
    for (std::sregex_iterator it(dims.begin(), dims.end(), number), end; it != end; ++it)
        h.shape.push_back(std::stoull(it->str()));
    return h;
}

NpyArray read_npy_f32(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
    const NpyHeader h = read_npy_header(in, path);
    if (h.float64) throw std::runtime_error(fmt::format("{}: not a float32 array", path));
    NpyArray a;
    a.shape = h.shape;
    std::size_t count = 1;
    for (const std::uint64_t d : h.shape)
        count *= d;
    a.values.resize(count);
    in.read(reinterpret_cast<char*>(a.values.data()), std::streamsize(count * sizeof(float)));
    if (!in) throw std::runtime_error(fmt::format("{}: truncated data", path));
    return a;
}

} // namespace fird
