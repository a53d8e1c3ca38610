#include "cpu_driver_lanes.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <pwd.h>
#include <unistd.h>

namespace fird::vk {

namespace {

constexpr const char* kWidthVariable = "LP_NATIVE_VECTOR_WIDTH";
constexpr const char* kCacheVariable = "MESA_SHADER_CACHE_DIR";

bool cpu_has_avx512() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    // The subsets llvmpipe's 512-bit code uses for float, 32-bit and narrower integers.
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#else
    return false;
#endif
}

std::string environment(const char* name) {
    const char* value = std::getenv(name);
    return value ? value : "";
}

// Where Mesa 22.3 keeps its cache folder (it adds "mesa_shader_cache" itself):
// MESA_SHADER_CACHE_DIR, else MESA_GLSL_CACHE_DIR, else the XDG cache home, else the
// user's home directory's .cache (from the password database, as Mesa reads it); empty if
// none is known. *off: Mesa's cache is off (disabled, or a cache folder set but empty).
std::filesystem::path cache_root(bool* off) {
    // Mesa's env_var_as_boolean: 1, true, y or yes (any case) turns the cache off.
    std::string disable = environment("MESA_SHADER_CACHE_DISABLE");
    std::transform(disable.begin(), disable.end(), disable.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    *off = disable == "1" || disable == "true" || disable == "y" || disable == "yes";
    for (const char* name : {kCacheVariable, "MESA_GLSL_CACHE_DIR"})
        if (const char* v = std::getenv(name)) {
            *off = *off || *v == '\0';
            return v;
        }
    if (std::string v = environment("XDG_CACHE_HOME"); !v.empty()) return v;
    std::vector<char> buffer(16384);
    passwd entry{};
    passwd* found = nullptr;
    if (getpwuid_r(getuid(), &entry, buffer.data(), buffer.size(), &found) == 0 && found &&
        found->pw_dir)
        return std::filesystem::path(found->pw_dir) / ".cache";
    return {};
}

// Moves this process's shader cache to a folder of `width`'s own beside Mesa's, or turns
// it off where no folder is known.
void separate_shader_cache(const std::string& width) {
    bool off = false;
    const std::filesystem::path root = cache_root(&off);
    if (off) return;
    if (root.empty()) {
        setenv("MESA_SHADER_CACHE_DISABLE", "true", /*overwrite=*/1);
        return;
    }
    const std::filesystem::path folder = root / ("lavapipe-" + width + "bit");
    // Mesa creates only the last level of its cache's path; a folder it cannot use turns
    // its cache off, which costs compile time and nothing else.
    std::error_code ignored;
    std::filesystem::create_directories(folder, ignored);
    setenv(kCacheVariable, folder.c_str(), /*overwrite=*/1);
}

} // namespace

void choose_cpu_driver_width(DeviceWork work) {
    std::string width = environment(kWidthVariable);
    if (width.empty() && work == DeviceWork::Compute && cpu_has_avx512() &&
        setenv(kWidthVariable, "512", /*overwrite=*/0) == 0)
        width = "512";
    // Mesa's own width (unset) keeps Mesa's own cache. A width that is not a number of
    // bits (llvmpipe takes 128, 256 or 512) is Mesa's to judge and names no folder.
    if (width.empty() || width.size() > 4 ||
        !std::all_of(width.begin(), width.end(), [](unsigned char c) { return std::isdigit(c); }))
        return;
    separate_shader_cache(width);
}

} // namespace fird::vk
