#include "ldt_reader.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "photometry_text.hpp"

namespace fird {

namespace {

constexpr long kMaxPlanes = 36000;
constexpr long kMaxLampSets = 1000;

// One numeric header line (decimal commas accepted, as some writers use them).
double header_number(const TextFile& f, std::size_t index, const char* what) {
    if (index >= f.lines.size())
        f.fail(f.lines.size(),
               fmt::format("line {} ({}): the file ends before it (truncated)", index + 1, what));
    std::string text(trim(f.lines[index]));
    std::replace(text.begin(), text.end(), ',', '.');
    return parse_number(f, {text, index + 1}, what);
}

long header_integer(const TextFile& f, std::size_t index, const char* what, long lo, long hi) {
    const double v = header_number(f, index, what);
    if (v != std::floor(v) || v < double(lo) || v > double(hi))
        f.fail(index + 1, fmt::format("{}: {} is not an integer in [{}, {}]", what, v, lo, hi));
    return long(v);
}

} // namespace

CandelaTable read_ldt_bytes(const std::string& path, std::string_view bytes) {
    const TextFile f = TextFile::from_bytes(path, bytes);
    if (f.lines.empty()) f.fail(0, "empty file");
    CandelaTable t;
    t.path = path;
    t.format = "ldt";
    t.version = "EULUMDAT";
    static constexpr const char* kTextFields[] = {"company",
                                                  "",
                                                  "",
                                                  "",
                                                  "",
                                                  "",
                                                  "",
                                                  "measurement report",
                                                  "luminaire name",
                                                  "luminaire number",
                                                  "file name",
                                                  "date / user"};
    for (std::size_t i : {0u, 7u, 8u, 9u, 10u, 11u})
        if (i < f.lines.size())
            t.keywords.emplace_back(kTextFields[i], utf8_from_legacy(trim(f.lines[i])));

    (void)header_integer(f, 1, "Ityp (type indicator)", 0, 3);
    const long isym = header_integer(f, 2, "Isym (symmetry indicator)", 0, 4);
    const long mc = header_integer(f, 3, "Mc (number of C planes)", 1, kMaxPlanes);
    (void)header_number(f, 4, "Dc (distance between C planes)");
    const long ng = header_integer(f, 5, "Ng (number of gamma angles)", 1, kMaxPlanes);
    (void)header_number(f, 6, "Dg (distance between gamma angles)");
    const double lorl = header_number(f, 22, "LORL (light output ratio, %)");
    const double cfli = header_number(f, 23, "conversion factor for luminous intensities");
    const long sets = header_integer(f, 25, "number of lamp sets", 1, kMaxLampSets);
    if (lorl < 0.0 || lorl > 1000.0) f.fail(23, fmt::format("LORL {} % is out of range", lorl));
    if (cfli <= 0.0) f.fail(24, "conversion factor for luminous intensities must be positive");

    // Lamp sets, each as six lines (number, type, flux, colour, CRI, watts). The first
    // set is the luminaire's rated equipment: its flux scales the cd/klm values.
    double set_flux = 0.0;
    long set_lamps = 0;
    for (long s = 0; s < sets; ++s) {
        const std::size_t base = 26 + std::size_t(s) * 6;
        const long lamps = header_integer(f, base, "number of lamps", -1000000, 1000000);
        const double flux = header_number(f, base + 2, "total luminous flux of lamps (lm)");
        if (flux <= 0.0) f.fail(base + 3, fmt::format("lamp flux {} lm must be positive", flux));
        if (s == 0) {
            set_flux = flux;
            set_lamps = lamps;
        }
        t.keywords.emplace_back(
            fmt::format("lamp set {}", s + 1),
            fmt::format("{} x {} ({} lm)", lamps, utf8_from_legacy(trim(f.lines[base + 1])), flux));
    }
    if (set_lamps == 0) f.fail(27, "number of lamps is 0");
    t.absolute = set_lamps < 0; // EULUMDAT's sign for absolute photometry
    t.flux_declared_lm = set_flux * lorl / 100.0;

    const std::size_t numbers_from = 26 + std::size_t(sets) * 6;
    // One number per line from here on; a line holding a single number may use a
    // decimal comma, other lines are split at blanks and commas.
    std::vector<Token> tokens;
    for (std::size_t l = numbers_from; l < f.lines.size(); ++l) {
        std::string text(trim(f.lines[l]));
        if (text.find_first_of(" \t") == std::string::npos && !text.empty()) {
            std::replace(text.begin(), text.end(), ',', '.');
            tokens.push_back({text, l + 1});
        } else {
            for (Token& tk : tokenize(f, l, l + 1))
                tokens.push_back(std::move(tk));
        }
    }
    TokenStream in(f, std::move(tokens));
    for (int k = 0; k < 10; ++k)
        (void)in.number("direct ratio");

    std::size_t stored = 0, first_plane = 0;
    switch (isym) {
    case 0:
        t.symmetry = Symmetry::None;
        stored = std::size_t(mc);
        break;
    case 1:
        t.symmetry = Symmetry::Rotational;
        stored = 1;
        break;
    case 2:
        t.symmetry = Symmetry::C0C180;
        stored = std::size_t(mc) / 2 + 1;
        break;
    case 3: // C270 through C0 to C90 (Mc1 = 3 Mc / 4 + 1 in EULUMDAT's 1-based terms)
        t.symmetry = Symmetry::C90C270;
        stored = std::size_t(mc) / 2 + 1;
        first_plane = 3 * std::size_t(mc) / 4;
        break;
    default:
        t.symmetry = Symmetry::Quadrant;
        stored = std::size_t(mc) / 4 + 1;
        break;
    }
    if ((isym == 2 && mc % 2 != 0) || ((isym == 3 || isym == 4) && mc % 4 != 0))
        f.fail(4, fmt::format("Mc = {} cannot hold symmetry Isym = {}", mc, isym));
    const std::size_t needed = std::size_t(mc) + std::size_t(ng) + stored * std::size_t(ng);
    if (needed > in.remaining())
        f.fail(in.line(), fmt::format("Mc = {}, Ng = {} and Isym = {} need {} numbers after the "
                                      "direct ratios; the file has {} (truncated or wrong counts)",
                                      mc, ng, isym, needed, in.remaining()));
    std::vector<double> c(static_cast<std::size_t>(mc)), g(static_cast<std::size_t>(ng));
    const std::size_t c_line = in.line();
    for (auto& a : c)
        a = in.number("C angle");
    const std::size_t g_line = in.line();
    for (auto& a : g)
        a = in.number("gamma angle");
    for (std::size_t i = 1; i < c.size(); ++i)
        if (!(c[i] > c[i - 1]))
            f.fail(c_line + i,
                   fmt::format("C angles are not increasing ({} then {})", c[i - 1], c[i]));
    for (std::size_t i = 1; i < g.size(); ++i)
        if (!(g[i] > g[i - 1]))
            f.fail(g_line + i,
                   fmt::format("gamma angles are not increasing ({} then {})", g[i - 1], g[i]));
    if (c.front() < 0.0 || c.back() >= 360.0)
        f.fail(c_line, fmt::format("C angles {} .. {} are outside [0, 360)", c.front(), c.back()));
    if (g.front() < 0.0 || g.back() > 180.0)
        f.fail(g_line,
               fmt::format("gamma angles {} .. {} are outside [0, 180]", g.front(), g.back()));

    const double scale = cfli * set_flux / 1000.0; // cd/klm -> cd
    std::vector<std::vector<double>> planes(stored, std::vector<double>(std::size_t(ng)));
    std::vector<double> stored_c(stored);
    for (std::size_t p = 0; p < stored; ++p) {
        stored_c[p] = c[(first_plane + p) % c.size()];
        for (auto& value : planes[p]) {
            const std::size_t line = in.line();
            const double v = in.number("luminous intensity (cd/klm)");
            if (v < 0.0)
                f.fail(line,
                       fmt::format("luminous intensity {} (C {}) is negative", v, stored_c[p]));
            value = v * scale;
        }
    }
    t.n_horizontal = std::size_t(mc);
    t.n_vertical = std::size_t(ng);
    t.gamma_deg = g;
    expand_symmetry(t, stored_c, planes);
    return t;
}

CandelaTable read_ldt(const std::string& path) {
    return read_ldt_bytes(path, read_bounded(path));
}

} // namespace fird
