#include "io/program_files.hpp"

#include <dlfcn.h>

#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "fird_module_stamp.h"

namespace fird {

namespace fs = std::filesystem;

std::string this_program() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw std::runtime_error(fmt::format("/proc/self/exe: {}", ec.message()));
    return exe.string();
}

namespace {

std::vector<fs::path> module_candidates(const std::string& file) {
    const fs::path dir = fs::path(this_program()).parent_path();
    return {dir.parent_path() / "lib" / file, dir / file};
}

struct LoadedModule {
    void* handle = nullptr;
    std::string path;
};

// The module, loaded. dlopen loads a module once per process and hands the same handle to
// every later call (it only counts them): no handle is kept here. Never closed.
LoadedModule load_module(const std::string& file) {
    std::string tried, reason;
    for (const fs::path& path : module_candidates(file)) {
        tried += (tried.empty() ? "" : ", ") + path.string();
        std::error_code ec;
        if (!fs::exists(path, ec)) continue;
        // Its symbols resolved now (a missing one fails here, not mid-search); local, so that
        // its libraries' symbols never stand in for the program's.
        if (void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) return {handle, path};
        const char* error = dlerror();
        reason = error ? error : "the loader gave no reason";
        break; // found but not loadable: say why, rather than try an older copy elsewhere
    }
    throw std::runtime_error(fmt::format("cannot load FIRD's module {} (looked for {}): {}", file,
                                         tried, reason.empty() ? "not found" : reason));
}

} // namespace

void* program_module_symbol(const std::string& file, const char* symbol) {
    const LoadedModule module = load_module(file);
    dlerror();
    void* address = dlsym(module.handle, symbol);
    if (!address)
        throw std::runtime_error(fmt::format("FIRD's module {} has no {}: it is from another build",
                                             module.path, symbol));
    return address;
}

void check_module_stamp(const std::string& file, const char* stamp) {
    if (!stamp || std::string_view(stamp) != FIRD_MODULE_STAMP)
        throw std::runtime_error(fmt::format("FIRD's module {} is from another build (engine "
                                             "headers {:.12}, this program's {:.12})",
                                             file, stamp ? stamp : "unknown", FIRD_MODULE_STAMP));
}

} // namespace fird
