#include "ies_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "photometry_text.hpp"

namespace fird {

namespace {

// Bounds far above any real file; with the token count check they keep allocations
// proportional to the file's size.
constexpr long kMaxAngles = 100000;

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
    if (s.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i)
        if (std::toupper(static_cast<unsigned char>(s[i])) != prefix[i]) return false;
    return true;
}

struct Version {
    std::string name;
    // Which line-10 factors scale the candela (LM-63-1986 to -1995: ballast factor and
    // ballast-lamp photometric factor; 2002: the second is "future use"; 2019: it is the
    // file generation type).
    bool second_factor_scales = false;
};

Version version_of(std::string_view first_line) {
    const std::string_view s = trim(first_line);
    if (starts_with_nocase(s, "IESNA:LM-63-1995")) return {"LM-63-1995", true};
    if (starts_with_nocase(s, "IESNA:LM-63-2002")) return {"LM-63-2002", false};
    if (starts_with_nocase(s, "IES:LM-63-2019") || starts_with_nocase(s, "IESNA:LM-63-2019"))
        return {"LM-63-2019", false};
    if (starts_with_nocase(s, "IESNA91")) return {"LM-63-1991", true};
    return {"LM-63-1986", true};
}

// The TILT factor at the luminaire's measured orientation (tilt 0), interpolated; the
// tilt block is: lamp-to-luminaire geometry, pair count, angles, factors.
double tilt_factor_at_zero(TokenStream& in) {
    (void)in.integer("TILT lamp-to-luminaire geometry", 1, 3);
    const long n = in.integer("TILT number of angle-factor pairs", 1, kMaxAngles);
    if (std::size_t(2 * n) > in.remaining())
        in.file().fail(in.line(), fmt::format("TILT: {} pairs announced, the file ends first", n));
    std::vector<double> angles(static_cast<std::size_t>(n)), factors(static_cast<std::size_t>(n));
    for (auto& a : angles)
        a = in.number("TILT angle");
    for (auto& f : factors) {
        f = in.number("TILT multiplying factor");
        if (f < 0.0) in.file().fail(in.line(), "TILT multiplying factor is negative");
    }
    for (std::size_t i = 1; i < angles.size(); ++i)
        if (!(angles[i] > angles[i - 1]))
            in.file().fail(in.line(), "TILT angles are not increasing");
    if (0.0 <= angles.front()) return factors.front();
    if (0.0 >= angles.back()) return factors.back();
    const std::size_t i =
        std::size_t(std::upper_bound(angles.begin(), angles.end(), 0.0) - angles.begin());
    const double w = (0.0 - angles[i - 1]) / (angles[i] - angles[i - 1]);
    return (1.0 - w) * factors[i - 1] + w * factors[i];
}

void check_increasing(const TextFile& f, std::size_t line, const std::vector<double>& a,
                      const char* what) {
    for (std::size_t i = 1; i < a.size(); ++i)
        if (!(a[i] > a[i - 1]))
            f.fail(line,
                   fmt::format("{} angles are not increasing ({} then {})", what, a[i - 1], a[i]));
}

// Bilinear sample of a type A / B grid (h outer, v inner); zero outside it. A grid that
// stores only H >= 0 is symmetric about H = 0 (LM-63: lateral symmetry).
double sample_hv(const std::vector<double>& h, const std::vector<double>& v,
                 const std::vector<double>& cd, double hq, double vq) {
    if (h.front() == 0.0 && h.back() > 0.0) hq = std::abs(hq);
    if (h.size() == 1) hq = h.front();
    if (hq < h.front() || hq > h.back() || vq < v.front() || vq > v.back()) return 0.0;
    const auto locate = [](const std::vector<double>& a, double x, std::size_t& i, double& w) {
        if (a.size() == 1) {
            i = 0;
            w = 0.0;
            return;
        }
        i = std::size_t(std::upper_bound(a.begin(), a.end(), x) - a.begin());
        i = std::min(std::max<std::size_t>(i, 1), a.size() - 1) - 1;
        w = (x - a[i]) / (a[i + 1] - a[i]);
    };
    std::size_t i = 0, j = 0;
    double wh = 0.0, wv = 0.0;
    locate(h, hq, i, wh);
    locate(v, vq, j, wv);
    const std::size_t nv = v.size();
    const std::size_t i1 = std::min(i + 1, h.size() - 1), j1 = std::min(j + 1, nv - 1);
    const double a = (1 - wv) * cd[i * nv + j] + wv * cd[i * nv + j1];
    const double b = (1 - wv) * cd[i1 * nv + j] + wv * cd[i1 * nv + j1];
    return (1 - wh) * a + wh * b;
}

Symmetry c_symmetry(const TextFile& f, std::size_t line, const std::vector<double>& h) {
    const double first = h.front(), last = h.back();
    if (h.size() == 1 && first == 0.0) return Symmetry::Rotational;
    if (first == 0.0 && last == 90.0) return Symmetry::Quadrant;
    if (first == 0.0 && last == 180.0) return Symmetry::C0C180;
    if (first == 90.0 && last == 270.0) return Symmetry::C90C270;
    if (first == 0.0 && last > 180.0 && last <= 360.0) return Symmetry::None;
    f.fail(line, fmt::format("horizontal angles {} .. {}: not a range LM-63 defines for type C "
                             "(0, 0-90, 0-180, 90-270, 0-360)",
                             first, last));
}

} // namespace

CandelaTable read_ies_bytes(const std::string& path, std::string_view bytes) {
    const TextFile f = TextFile::from_bytes(path, bytes);
    if (f.lines.empty()) f.fail(0, "empty file");
    CandelaTable t;
    t.path = path;
    t.format = "ies";
    const Version version = version_of(f.lines.front());
    t.version = version.name;

    // Keywords (2002, 2019: "[KEY] value", continued by [MORE]); 1986: free label lines.
    std::size_t l = version.name == "LM-63-1986" ? 0 : 1;
    std::size_t tilt_line = f.lines.size();
    for (; l < f.lines.size(); ++l) {
        const std::string_view s = trim(f.lines[l]);
        if (starts_with_nocase(s, "TILT=") || starts_with_nocase(s, "TILT =")) {
            tilt_line = l;
            break;
        }
        if (s.size() > 1 && s.front() == '[' && s.find(']') != std::string_view::npos) {
            const std::size_t close = s.find(']');
            const std::string key = utf8_from_legacy(s.substr(1, close - 1));
            const std::string value = utf8_from_legacy(trim(s.substr(close + 1)));
            if (key == "MORE" && !t.keywords.empty())
                t.keywords.back().second += "\n" + value;
            else
                t.keywords.emplace_back(key, value);
        } else if (!s.empty()) {
            t.keywords.emplace_back("", utf8_from_legacy(s)); // a 1986-style label line
        }
    }
    if (tilt_line == f.lines.size()) f.fail(0, "no TILT= line (is this an IES LM-63 file?)");
    const std::string_view tilt =
        trim(trim(f.lines[tilt_line]).substr(trim(f.lines[tilt_line]).find('=') + 1));

    TokenStream in(f, tokenize(f, tilt_line + 1, f.lines.size()));
    double tilt_factor = 1.0;
    if (starts_with_nocase(tilt, "INCLUDE")) {
        tilt_factor = tilt_factor_at_zero(in);
    } else if (!starts_with_nocase(tilt, "NONE")) {
        const auto tilt_path =
            (std::filesystem::path(path).parent_path() / std::string(tilt)).string();
        const TextFile tf = TextFile::load(tilt_path);
        TokenStream tin(tf, tokenize(tf, 0, tf.lines.size()));
        tilt_factor = tilt_factor_at_zero(tin);
    }

    const long lamps = in.integer("number of lamps", 1, 1000000);
    const double lumens = in.number("lumens per lamp");
    const std::size_t lumens_line = in.line();
    const double multiplier = in.number("candela multiplier");
    const long nv = in.integer("number of vertical angles", 1, kMaxAngles);
    const long nh = in.integer("number of horizontal angles", 1, kMaxAngles);
    const long type = in.integer("photometric type", 1, 3);
    (void)in.integer("units type", 1, 2);
    (void)in.number("luminous width");
    (void)in.number("luminous length");
    (void)in.number("luminous height");
    const double ballast = in.number("ballast factor");
    const double second =
        in.number(version.second_factor_scales ? "ballast-lamp photometric factor"
                                               : "future use / file generation type");
    (void)in.number("input watts");
    if (lumens <= 0.0 && lumens != -1.0)
        f.fail(lumens_line,
               fmt::format("lumens per lamp {}: must be positive or -1 (absolute)", lumens));
    if (multiplier <= 0.0) f.fail(lumens_line, "candela multiplier must be positive");
    if (ballast <= 0.0) f.fail(in.line(), "ballast factor must be positive");
    const std::size_t n_values = std::size_t(nv) * std::size_t(nh);
    if (std::size_t(nv + nh) + n_values > in.remaining())
        f.fail(in.line(), fmt::format("{} vertical and {} horizontal angles need {} numbers; the "
                                      "file has {} left (truncated or wrong counts)",
                                      nv, nh, std::size_t(nv + nh) + n_values, in.remaining()));

    std::vector<double> v(static_cast<std::size_t>(nv)), h(static_cast<std::size_t>(nh));
    const std::size_t v_line = in.line();
    for (auto& a : v)
        a = in.number("vertical angle");
    const std::size_t h_line = in.line();
    for (auto& a : h)
        a = in.number("horizontal angle");
    check_increasing(f, v_line, v, "vertical");
    check_increasing(f, h_line, h, "horizontal");
    double scale = multiplier * ballast * tilt_factor;
    if (version.second_factor_scales) {
        if (second <= 0.0) f.fail(h_line, "ballast-lamp photometric factor must be positive");
        scale *= second;
    }
    std::vector<double> cd(n_values);
    for (std::size_t i = 0; i < n_values; ++i) {
        const std::size_t line = in.line();
        const double value = in.number("candela value");
        if (value < 0.0)
            f.fail(line, fmt::format("candela value {} (horizontal angle {}, vertical angle {}) "
                                     "is negative",
                                     value, h[i / std::size_t(nv)], v[i % std::size_t(nv)]));
        cd[i] = value * scale;
    }
    if (in.remaining() > 0)
        t.keywords.emplace_back("_FIRD_TRAILING", fmt::format("{} numbers after the candela "
                                                              "values were ignored",
                                                              in.remaining()));

    t.n_vertical = std::size_t(nv);
    t.n_horizontal = std::size_t(nh);
    t.absolute = lumens == -1.0;
    if (!t.absolute) t.flux_declared_lm = double(lamps) * lumens;
    if (type == 1) {
        if (v.front() < 0.0 || v.back() > 180.0)
            f.fail(v_line, fmt::format("vertical angles {} .. {}: type C needs 0 .. 180", v.front(),
                                       v.back()));
        t.file_type = PhotometricType::C;
        t.symmetry = c_symmetry(f, h_line, h);
        t.gamma_deg = v;
        std::vector<std::vector<double>> planes(static_cast<std::size_t>(nh));
        for (std::size_t p = 0; p < planes.size(); ++p)
            planes[p].assign(cd.begin() + std::ptrdiff_t(p * std::size_t(nv)),
                             cd.begin() + std::ptrdiff_t((p + 1) * std::size_t(nv)));
        expand_symmetry(t, h, planes);
    } else {
        t.file_type = type == 2 ? PhotometricType::B : PhotometricType::A;
        if (v.front() < -90.0 || v.back() > 90.0 || h.front() < -180.0 || h.back() > 180.0)
            f.fail(v_line, fmt::format("type {} angles out of range (V in -90 .. 90, H in "
                                       "-180 .. 180)",
                                       to_string(t.file_type)));
        t.symmetry = Symmetry::None;
        resample_to_type_c(t, t.file_type,
                           [&](double hq, double vq) { return sample_hv(h, v, cd, hq, vq); });
    }
    return t;
}

CandelaTable read_ies(const std::string& path) {
    return read_ies_bytes(path, read_bounded(path));
}

} // namespace fird
