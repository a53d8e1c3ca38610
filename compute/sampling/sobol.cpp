#include "sobol.hpp"

#include "philox.hpp"

namespace fird {

namespace {

// Direction numbers v[d][b] (as 32-bit fractions) for dimensions 0..3 from the primitive
// polynomials x, x+1, x^2+x+1, x^3+x+1 with initial numbers m = (1), (1), (1,3),
// (1,3,1): the standard construction (Bratley & Fox; Joe & Kuo's first dimensions).
struct Directions {
    std::uint32_t v[4][32];
    Directions() {
        for (int b = 0; b < 32; ++b)
            v[0][b] = 1u << (31 - b); // van der Corput
        struct Poly {
            int degree;
            std::uint32_t a; // inner coefficients
            std::uint32_t m[3];
        };
        const Poly polys[3] = {{1, 0u, {1, 0, 0}}, {2, 1u, {1, 3, 0}}, {3, 1u, {1, 3, 1}}};
        for (int d = 1; d < 4; ++d) {
            const Poly& p = polys[d - 1];
            const int s = p.degree;
            for (int b = 0; b < s; ++b)
                v[d][b] = p.m[b] << (31 - b);
            for (int b = s; b < 32; ++b) {
                std::uint32_t x = v[d][b - s] ^ (v[d][b - s] >> s);
                for (int k = 1; k < s; ++k)
                    if ((p.a >> (s - 1 - k)) & 1u) x ^= v[d][b - k];
                v[d][b] = x;
            }
        }
    }
};

const Directions& directions() {
    static const Directions d; // immutable table, built once
    return d;
}

std::uint32_t reverse_bits(std::uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
    x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
    return (x >> 16) | (x << 16);
}

// Laine-Karras style permutation: each output bit depends only on the input bits below
// it, so applied to bit-reversed values it is a nested uniform (Owen) scramble.
std::uint32_t lk_permute(std::uint32_t x, std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
    return reverse_bits(lk_permute(reverse_bits(x), seed));
}

} // namespace

SobolTables sobol_tables(std::uint64_t seed) {
    SobolTables t{};
    const auto& v = directions().v;
    for (int d = 0; d < 4; ++d)
        for (int b = 0; b < 32; ++b)
            t.directions[d][b] = v[d][b];
    // Per-seed scramble seeds come from Philox keyed by the seed, not from XOR-ed hashes.
    const std::array<std::uint32_t, 2> key{std::uint32_t(seed), std::uint32_t(seed >> 32)};
    const Philox4 seeds = philox4x32_10({0u, 0u, 0x50B01u, 0u}, key);
    const Philox4 more = philox4x32_10({1u, 0u, 0x50B01u, 0u}, key);
    for (int d = 0; d < 4; ++d)
        t.scramble[d] = seeds[d];
    t.scramble[4] = more[0];
    return t;
}

std::array<double, 4> sobol_uniforms(std::uint64_t seed, std::uint64_t index) {
    const SobolTables tables = sobol_tables(seed);
    const Philox4 seeds{tables.scramble[0], tables.scramble[1], tables.scramble[2],
                        tables.scramble[3]};
    const std::uint32_t i = owen_scramble(std::uint32_t(index), tables.scramble[4]);
    const auto& v = tables.directions;
    std::array<double, 4> u{};
    for (int d = 0; d < 4; ++d) {
        std::uint32_t x = 0;
        for (std::uint32_t bits = i, b = 0; bits; bits >>= 1, ++b)
            if (bits & 1u) x ^= v[d][b];
        x = owen_scramble(x, seeds[d]);
        u[d] = (double(x) + 0.5) * 0x1p-32;
    }
    return u;
}

} // namespace fird
