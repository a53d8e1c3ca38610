#include "sha256.hpp"

#include <array>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <nettle/sha2.h>

namespace fird {

namespace {

// Nettle (GnuTLS's hash library) computes the digest; this file only feeds it and prints
// the bytes as sha256sum does.
std::string hex_digest(sha256_ctx& ctx) {
    std::array<std::uint8_t, SHA256_DIGEST_SIZE> digest{};
    sha256_digest(&ctx, digest.size(), digest.data());
    std::string hex;
    for (std::uint8_t b : digest)
        hex += fmt::format("{:02x}", b);
    return hex;
}

} // namespace

std::string sha256_hex(std::string_view bytes) {
    sha256_ctx ctx;
    sha256_init(&ctx);
    sha256_update(&ctx, bytes.size(), reinterpret_cast<const std::uint8_t*>(bytes.data()));
    return hex_digest(ctx);
}

std::string file_sha256_hex(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
    sha256_ctx ctx;
    sha256_init(&ctx);
    std::vector<char> buffer(1 << 16);
    for (;;) {
        in.read(buffer.data(), std::streamsize(buffer.size()));
        const auto got = std::size_t(in.gcount());
        sha256_update(&ctx, got, reinterpret_cast<const std::uint8_t*>(buffer.data()));
        if (got < buffer.size()) {
            if (in.bad()) throw std::runtime_error(fmt::format("{}: cannot read", path));
            return hex_digest(ctx);
        }
    }
}

} // namespace fird
