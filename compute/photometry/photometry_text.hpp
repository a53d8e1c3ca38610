// Reading photometric files as text: bounded loading, lines (LF, CRLF or CR), numbers
// as a stream of tokens that remember their line, and errors that name file and line.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace fird {

// "FILE:LINE: message" (line 0: the whole file).
class PhotometryError : public std::runtime_error {
  public:
    PhotometryError(const std::string& file, std::size_t line, const std::string& message);
};

// The file's bytes; throws PhotometryError when it cannot be read or is larger than
// any photometric file (a bound, so a wrong path cannot allocate without limit).
std::string read_bounded(const std::string& path);

struct TextFile {
    std::string path;
    std::vector<std::string> lines; // without line ends

    // Throws PhotometryError when the file cannot be read or exceeds the size bound.
    static TextFile load(const std::string& path);
    // From bytes in memory (fuzzing, tests); `path` names them in messages.
    static TextFile from_bytes(std::string path, std::string_view bytes);

    [[noreturn]] void fail(std::size_t line, const std::string& message) const;
};

struct Token {
    std::string text;
    std::size_t line; // 1-based
};

// Number tokens of lines [first, end), split at blanks, tabs and commas.
std::vector<Token> tokenize(const TextFile& file, std::size_t first_line, std::size_t end_line);

// Reads a finite number (a leading '+' and '.5' are accepted), or fails naming `what`.
double parse_number(const TextFile& file, const Token& token, const std::string& what);

// A sequential reader of tokens: next() fails with `what` when the tokens run out.
class TokenStream {
  public:
    TokenStream(const TextFile& file, std::vector<Token> tokens)
        : file_(&file), tokens_(std::move(tokens)) {}
    double number(const std::string& what);
    // An integer in [lo, hi]; fails on fractions and out-of-range values.
    long integer(const std::string& what, long lo, long hi);
    std::size_t remaining() const { return tokens_.size() - next_; }
    std::size_t line() const; // of the next token (or the last)
    const TextFile& file() const { return *file_; }

  private:
    const Token& next(const std::string& what);
    const TextFile* file_;
    std::vector<Token> tokens_;
    std::size_t next_ = 0;
};

// The bytes as UTF-8: kept when valid, else read as Latin-1 (older files' encoding).
std::string utf8_from_legacy(std::string_view bytes);

// Leading and trailing blanks removed.
std::string_view trim(std::string_view s);

} // namespace fird
