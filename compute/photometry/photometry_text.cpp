#include "photometry_text.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace fird {

namespace {
// Real IES and LDT files are kilobytes; a bound keeps a wrong path (or a hostile file)
// from allocating without limit.
constexpr std::size_t kMaxFileBytes = 64u << 20;
} // namespace

PhotometryError::PhotometryError(const std::string& file, std::size_t line,
                                 const std::string& message)
    : std::runtime_error(line ? fmt::format("{}:{}: {}", file, line, message)
                              : fmt::format("{}: {}", file, message)) {}

std::string read_bounded(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw PhotometryError(path, 0, "cannot open the file");
    in.seekg(0, std::ios::end);
    const auto size = in.tellg();
    if (size < 0) throw PhotometryError(path, 0, "cannot read the file");
    if (std::size_t(size) > kMaxFileBytes)
        throw PhotometryError(path, 0,
                              fmt::format("{} bytes: larger than any photometric file "
                                          "(limit {} MiB)",
                                          std::size_t(size), kMaxFileBytes >> 20));
    in.seekg(0);
    std::string bytes(std::size_t(size), '\0');
    in.read(bytes.data(), size);
    if (!in) throw PhotometryError(path, 0, "cannot read the file");
    return bytes;
}

TextFile TextFile::load(const std::string& path) {
    return from_bytes(path, read_bounded(path));
}

TextFile TextFile::from_bytes(std::string path, std::string_view bytes) {
    TextFile f;
    f.path = std::move(path);
    std::string line;
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const char c = bytes[i];
        if (c == '\r' || c == '\n') {
            f.lines.push_back(std::move(line));
            line.clear();
            if (c == '\r' && i + 1 < bytes.size() && bytes[i + 1] == '\n') ++i;
        } else {
            line.push_back(c);
        }
    }
    if (!line.empty()) f.lines.push_back(std::move(line));
    return f;
}

void TextFile::fail(std::size_t line, const std::string& message) const {
    throw PhotometryError(path, line, message);
}

std::vector<Token> tokenize(const TextFile& file, std::size_t first, std::size_t end) {
    std::vector<Token> tokens;
    for (std::size_t l = first; l < end && l < file.lines.size(); ++l) {
        const std::string& s = file.lines[l];
        std::size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() &&
                   (s[i] == ' ' || s[i] == '\t' || s[i] == ',' || s[i] == '\f' || s[i] == '\v'))
                ++i;
            const std::size_t start = i;
            while (i < s.size() &&
                   !(s[i] == ' ' || s[i] == '\t' || s[i] == ',' || s[i] == '\f' || s[i] == '\v'))
                ++i;
            if (i > start) tokens.push_back({s.substr(start, i - start), l + 1});
        }
    }
    return tokens;
}

double parse_number(const TextFile& file, const Token& token, const std::string& what) {
    std::string_view s = token.text;
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v) || s.empty())
        file.fail(token.line, fmt::format("{}: expected a number, found '{}'", what,
                                          utf8_from_legacy(token.text.substr(0, 40))));
    return v;
}

const Token& TokenStream::next(const std::string& what) {
    if (next_ >= tokens_.size())
        file_->fail(tokens_.empty() ? 0 : tokens_.back().line,
                    fmt::format("{}: the file ends before it (truncated)", what));
    return tokens_[next_++];
}

double TokenStream::number(const std::string& what) {
    const Token& t = next(what);
    return parse_number(*file_, t, what);
}

long TokenStream::integer(const std::string& what, long lo, long hi) {
    const Token& t = next(what);
    const double v = parse_number(*file_, t, what);
    if (v != std::floor(v) || v < double(lo) || v > double(hi))
        file_->fail(t.line,
                    fmt::format("{}: {} is not an integer in [{}, {}]", what, t.text, lo, hi));
    return long(v);
}

std::size_t TokenStream::line() const {
    if (tokens_.empty()) return 0;
    return next_ < tokens_.size() ? tokens_[next_].line : tokens_.back().line;
}

std::string utf8_from_legacy(std::string_view bytes) {
    // Valid UTF-8?
    bool valid = true;
    for (std::size_t i = 0; i < bytes.size() && valid;) {
        const auto c = static_cast<unsigned char>(bytes[i]);
        std::size_t n = c < 0x80         ? 1
                        : (c >> 5) == 6  ? 2
                        : (c >> 4) == 14 ? 3
                        : (c >> 3) == 30 ? 4
                                         : 0;
        if (n == 0 || i + n > bytes.size()) {
            valid = false;
            break;
        }
        for (std::size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(bytes[i + k]) >> 6) != 2) valid = false;
        i += n;
    }
    if (valid) return std::string(bytes);
    std::string out;
    for (const char ch : bytes) {
        const auto c = static_cast<unsigned char>(ch);
        if (c < 0x80) {
            out.push_back(ch);
        } else {
            out.push_back(char(0xC0 | (c >> 6)));
            out.push_back(char(0x80 | (c & 0x3F)));
        }
    }
    return out;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
        s.remove_suffix(1);
    return s;
}

} // namespace fird
