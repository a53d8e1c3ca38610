#include "atomic_file.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>
#include <unistd.h>

namespace fird {

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary)>& write) {
    namespace fs = std::filesystem;
    const fs::path target(path);
    const fs::path temporary =
        target.parent_path() / fmt::format(".{}.tmp-{}", target.filename().string(), ::getpid());
    try {
        write(temporary.string());
        std::error_code ec;
        fs::rename(temporary, target, ec);
        if (ec) throw std::runtime_error(fmt::format("{}: cannot write: {}", path, ec.message()));
    } catch (...) {
        std::error_code ignored;
        fs::remove(temporary, ignored);
        throw;
    }
}

void write_text_file(const std::string& path, const std::string& text) {
    write_atomically(path, [&](const std::string& temporary) {
        std::ofstream out(temporary, std::ios::binary);
        if (!out) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
        out << text;
        out.close();
        if (!out) throw std::runtime_error(fmt::format("{}: write failed", path));
    });
}

void create_output_directory(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
        throw std::runtime_error(fmt::format(
            "{}: cannot create the output directory{}", dir,
            ec ? ": " + ec.message() : std::string(": a file of that name is in the way")));
}

} // namespace fird
