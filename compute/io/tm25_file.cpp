#include "tm25_file.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace fird {

namespace {

// The fixed part: the file header block (256 bytes), the known-data flags (8 x 4 bytes)
// and nine description fields of 1000 UTF-32 code points.
constexpr std::uint64_t kFlagsAt = 256;
constexpr std::uint64_t kTextAt = 288;
constexpr std::uint64_t kTextBytes = 4000;
constexpr std::uint64_t kFixedBytes = kTextAt + 9 * kTextBytes; // 36288
constexpr std::uint64_t kColumnNameBytes = 512; // an additional column's name (UTF-32)

std::uint32_t u32_at(const std::vector<char>& b, std::uint64_t at) {
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k)
        v = (v << 8) | std::uint8_t(b[at + std::uint64_t(k)]);
    return v;
}
std::uint32_t swapped(std::uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0xFF00u) | ((v << 8) & 0xFF0000u) | (v << 24);
}
std::int32_t i32_at(const std::vector<char>& b, std::uint64_t at) {
    return std::bit_cast<std::int32_t>(u32_at(b, at));
}

// UTF-32LE, NUL-terminated or padded, as UTF-8 (code points past Unicode read as '?').
std::string utf8_of_utf32(const std::vector<char>& b, std::uint64_t at, std::uint64_t bytes) {
    std::string s;
    for (std::uint64_t i = 0; i + 4 <= bytes; i += 4) {
        std::uint32_t c = u32_at(b, at + i);
        if (c == 0) break;
        if (c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) c = '?';
        if (c < 0x80) {
            s.push_back(char(c));
        } else if (c < 0x800) {
            s.push_back(char(0xC0 | (c >> 6)));
            s.push_back(char(0x80 | (c & 0x3F)));
        } else if (c < 0x10000) {
            s.push_back(char(0xE0 | (c >> 12)));
            s.push_back(char(0x80 | ((c >> 6) & 0x3F)));
            s.push_back(char(0x80 | (c & 0x3F)));
        } else {
            s.push_back(char(0xF0 | (c >> 18)));
            s.push_back(char(0x80 | ((c >> 12) & 0x3F)));
            s.push_back(char(0x80 | ((c >> 6) & 0x3F)));
            s.push_back(char(0x80 | (c & 0x3F)));
        }
    }
    return s;
}

} // namespace

Tm25Header read_tm25_header(std::istream& in, std::uint64_t file_bytes, const std::string& path) {
    const auto fail = [&](std::uint64_t at, const std::string& what) {
        throw std::runtime_error(fmt::format("{}: byte {}: {}", path, at, what));
    };
    if (file_bytes < 8) fail(file_bytes, "short file: not a TM-25 ray file");
    std::vector<char> b(std::size_t(std::min(file_bytes, kFixedBytes)));
    in.read(b.data(), std::streamsize(b.size()));
    if (!in) fail(0, "cannot read the header");
    if (std::memcmp(b.data(), "TM25", 4) != 0)
        fail(0,
             fmt::format("tag '{}', not 'TM25': not a TM-25 ray file", std::string(b.data(), 4)));
    if (const std::int32_t version = i32_at(b, 4); version != 2013)
        fail(4, fmt::format("version {}; the 2013 layout is read", version));
    if (file_bytes < kFixedBytes)
        fail(file_bytes,
             fmt::format("short file: the header's fixed part needs {} bytes", kFixedBytes));
    Tm25Header h;
    // A flux total: NaN or 0 where unknown; a NaN written big-endian reads here as a
    // denormal whose bytes, swapped, are a NaN (files from big-endian writers).
    const auto flux_at = [&](std::uint64_t at, const char* what) {
        const std::uint32_t bits = u32_at(b, at);
        const float f = std::bit_cast<float>(bits);
        if (std::fpclassify(f) == FP_SUBNORMAL && std::isnan(std::bit_cast<float>(swapped(bits)))) {
            h.flux_nan_swapped = true;
            return std::numeric_limits<double>::quiet_NaN();
        }
        if (std::isinf(f) || f < 0.0f) fail(at, fmt::format("{} {}: must be >= 0", what, f));
        return f > 0.0f ? double(f) : std::numeric_limits<double>::quiet_NaN();
    };
    h.luminous_flux_lm = flux_at(12, "luminous flux");
    h.radiant_flux_w = flux_at(16, "radiant flux");
    h.rays = std::uint64_t(u32_at(b, 20)) | (std::uint64_t(u32_at(b, 24)) << 32);
    if (const std::int32_t id = i32_at(b, 60); id < 0 || id > 4)
        fail(60, fmt::format("spectral data identifier {}: must be 0 to 4", id));
    const std::int32_t spectra = i32_at(b, 76);
    if (spectra < 0 || spectra > 100000) fail(76, fmt::format("{} spectral tables", spectra));
    const std::int32_t additional = i32_at(b, 80);
    if (additional < 0 || additional > 10000)
        fail(80, fmt::format("{} additional ray items", additional));
    const std::int32_t text_bytes = i32_at(b, 84);
    if (text_bytes < 0) fail(84, fmt::format("additional text of {} bytes", text_bytes));
    for (int k = 0; k < 8; ++k) {
        const std::int32_t flag = i32_at(b, kFlagsAt + 4 * std::uint64_t(k));
        if (flag != 0 && flag != 1)
            fail(kFlagsAt + 4 * std::uint64_t(k), fmt::format("flag {}: must be 0 or 1", flag));
        h.flags[std::size_t(k)] = flag == 1;
    }
    if (!h.flags[0] || !h.flags[1]) fail(kFlagsAt, "the position and direction flags must be 1");
    // Columns (4.7.7): x y z kx ky kz, then radiant flux, wavelength, luminous flux, the
    // Stokes parameters and polarisation ellipse (6), tristimulus X and Z (2), spectrum
    // index, and the additional items, each where flagged.
    std::uint32_t c = 6;
    if (h.flags[2]) h.radiant_column = int(c++);
    if (h.flags[3]) ++c;
    if (h.flags[4]) h.luminous_column = int(c++);
    c += (h.flags[5] ? 6u : 0u) + (h.flags[6] ? 2u : 0u) + (h.flags[7] ? 1u : 0u);
    h.columns = c + std::uint32_t(additional);
    for (std::size_t k = 0; k < 9; ++k)
        h.text[k] = utf8_of_utf32(b, kTextAt + k * kTextBytes, kTextBytes);
    // The spectral tables (4.7.4): a point count and as many (wavelength, value) pairs
    // each, padded together to a multiple of 32 bytes.
    std::uint64_t at = kFixedBytes;
    for (std::int32_t t = 0; t < spectra; ++t) {
        if (at + 4 > file_bytes) fail(at, "short file: a spectral table is cut off");
        std::vector<char> count(4);
        in.seekg(std::streamoff(at));
        in.read(count.data(), 4);
        if (!in) fail(at, "cannot read a spectral table");
        const std::int32_t points = i32_at(count, 0);
        if (points <= 0 || points > 1000000)
            fail(at, fmt::format("a spectral table of {} points", points));
        at += 4 + 8 * std::uint64_t(points);
    }
    const std::uint64_t tables = at - kFixedBytes;
    const std::uint64_t padding = (32 - tables % 32) % 32;
    const std::uint64_t after_tables =
        std::uint64_t(additional) * kColumnNameBytes + std::uint64_t(text_bytes);
    const std::uint64_t record_bytes = 4ull * h.columns;
    if (h.rays > (std::numeric_limits<std::uint64_t>::max() - file_bytes) / record_bytes)
        fail(20, fmt::format("{} rays: more than any file holds", h.rays));
    const std::uint64_t ray_bytes = h.rays * record_bytes;
    h.ray_offset = at + padding + after_tables;
    if (h.ray_offset + ray_bytes != file_bytes) {
        if (padding > 0 && at + after_tables + ray_bytes == file_bytes) {
            h.padding_missing = true;
            h.ray_offset = at + after_tables;
        } else if (file_bytes < h.ray_offset + ray_bytes) {
            fail(h.ray_offset,
                 fmt::format("short file: the header's {} rays of {} bytes need {} bytes from "
                             "here, the file has {}: the header disagrees with the file's size",
                             h.rays, record_bytes, ray_bytes,
                             file_bytes > h.ray_offset ? file_bytes - h.ray_offset : 0));
        } else {
            fail(h.ray_offset,
                 fmt::format("the header's {} rays of {} bytes need {} bytes from here, the "
                             "file has {}: the header disagrees with the file's size",
                             h.rays, record_bytes, ray_bytes, file_bytes - h.ray_offset));
        }
    }
    return h;
}

} // namespace fird
