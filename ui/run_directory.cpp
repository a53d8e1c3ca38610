#include "run_directory.hpp"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

namespace fird::ui {

std::string runs_directory() {
    namespace fs = std::filesystem;
    if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x)
        return (fs::path(x) / "fird" / "runs").string();
    if (const char* h = std::getenv("HOME"); h && *h)
        return (fs::path(h) / ".local" / "share" / "fird" / "runs").string();
    return "fird_runs";
}

std::string new_run_directory(const std::string& base, const std::string& stem,
                              const std::string& job) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(base, ec);
    if (ec)
        throw std::runtime_error(
            fmt::format("{}: cannot create the folder: {}", base, ec.message()));
    // A bounded search: a folder holding a million runs is a mistake, not a reason to loop.
    for (int n = 1; n <= 1000000; ++n) {
        const fs::path dir = fs::path(base) / fmt::format("{}-{}-{}", stem, job, n);
        if (fs::create_directory(dir, ec)) return fs::absolute(dir).string();
        if (ec)
            throw std::runtime_error(
                fmt::format("{}: cannot create the folder: {}", dir.string(), ec.message()));
    }
    throw std::runtime_error(fmt::format("{}: no free run folder name", base));
}

} // namespace fird::ui
