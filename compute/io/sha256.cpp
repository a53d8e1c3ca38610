#include "sha256.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace fird {

namespace {

// FIPS 180-4 §4.2.2: the first 32 bits of the fractional parts of the cube roots of the
// first 64 primes.
constexpr std::array<std::uint32_t, 64> kRound = {
    0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4, 0xab1c5ed5,
    0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe, 0x9bdc06a7, 0xc19bf174,
    0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f, 0x4a7484aa, 0x5cb0a9dc, 0x76f988da,
    0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7, 0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967,
    0x27b70a85, 0x2e1b2138, 0x4d2c6dfc, 0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85,
    0xa2bfe8a1, 0xa81a664b, 0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070,
    0x19a4c116, 0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
    0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7, 0xc67178f2};

// The digest so far, fed 64-byte blocks.
struct Sha256 {
    // §5.3.3: the square roots of the first 8 primes.
    std::array<std::uint32_t, 8> h = {0x6a09e667, 0xbb67ae85, 0x3c6ef372, 0xa54ff53a,
                                      0x510e527f, 0x9b05688c, 0x1f83d9ab, 0x5be0cd19};

    void block(const unsigned char* p) {
        std::array<std::uint32_t, 64> w{};
        for (int t = 0; t < 16; ++t)
            w[t] = std::uint32_t(p[4 * t]) << 24 | std::uint32_t(p[4 * t + 1]) << 16 |
                   std::uint32_t(p[4 * t + 2]) << 8 | std::uint32_t(p[4 * t + 3]);
        for (int t = 16; t < 64; ++t) {
            const std::uint32_t s0 =
                std::rotr(w[t - 15], 7) ^ std::rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
            const std::uint32_t s1 =
                std::rotr(w[t - 2], 17) ^ std::rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
            w[t] = w[t - 16] + s0 + w[t - 7] + s1;
        }
        auto [a, b, c, d, e, f, g, k] = h;
        for (int t = 0; t < 64; ++t) {
            const std::uint32_t t1 = k + (std::rotr(e, 6) ^ std::rotr(e, 11) ^ std::rotr(e, 25)) +
                                     ((e & f) ^ (~e & g)) + kRound[t] + w[t];
            const std::uint32_t t2 = (std::rotr(a, 2) ^ std::rotr(a, 13) ^ std::rotr(a, 22)) +
                                     ((a & b) ^ (a & c) ^ (b & c));
            k = g;
            g = f;
            f = e;
            e = d + t1;
            d = c;
            c = b;
            b = a;
            a = t1 + t2;
        }
        const std::array<std::uint32_t, 8> add{a, b, c, d, e, f, g, k};
        for (int i = 0; i < 8; ++i)
            h[i] += add[i];
    }

    // §5.1.1: a 1 bit, zeros to 56 bytes mod 64, the message length in bits (big-endian).
    std::string finish(const unsigned char* tail, std::size_t tail_bytes, std::uint64_t bytes) {
        std::vector<unsigned char> last(tail, tail + tail_bytes);
        last.push_back(0x80);
        while (last.size() % 64 != 56)
            last.push_back(0);
        for (int i = 7; i >= 0; --i)
            last.push_back(static_cast<unsigned char>((bytes * 8) >> (8 * i)));
        for (std::size_t i = 0; i < last.size(); i += 64)
            block(last.data() + i);
        std::string hex;
        for (std::uint32_t v : h)
            hex += fmt::format("{:08x}", v);
        return hex;
    }
};

} // namespace

std::string sha256_hex(std::string_view bytes) {
    Sha256 s;
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
    const std::size_t whole = bytes.size() / 64 * 64;
    for (std::size_t i = 0; i < whole; i += 64)
        s.block(p + i);
    return s.finish(p + whole, bytes.size() - whole, bytes.size());
}

std::string file_sha256_hex(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
    Sha256 s;
    std::vector<char> buffer(1 << 16); // a multiple of the 64-byte block
    std::uint64_t bytes = 0;
    for (;;) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        const auto got = std::size_t(in.gcount());
        bytes += got;
        const auto* p = reinterpret_cast<const unsigned char*>(buffer.data());
        const std::size_t whole = got / 64 * 64;
        for (std::size_t i = 0; i < whole; i += 64)
            s.block(p + i);
        if (got < buffer.size()) {
            if (in.bad()) throw std::runtime_error(fmt::format("{}: cannot read", path));
            return s.finish(p + whole, got - whole, bytes);
        }
    }
}

} // namespace fird
