// SHA-256 (FIPS 180-4) of a file's contents: how a search's record (options.json) names
// the files its result depends on, so --resume can tell when one changed. The hex digest
// is what `sha256sum` prints, so a record can be checked by hand.
#pragma once

#include <string>
#include <string_view>

namespace fird {

// The lowercase hex digest of `bytes`.
std::string sha256_hex(std::string_view bytes);

// The lowercase hex digest of the file's contents; std::runtime_error naming the path when
// it cannot be read.
std::string file_sha256_hex(const std::string& path);

} // namespace fird
