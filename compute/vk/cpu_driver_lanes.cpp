#include "cpu_driver_lanes.hpp"

#include <cstdlib>

namespace fird::vk {

namespace {

constexpr const char* kWidthVariable = "LP_NATIVE_VECTOR_WIDTH";

bool cpu_has_avx512() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    // The subsets llvmpipe's 512-bit code uses for float, 32-bit and narrower integers.
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
#else
    return false;
#endif
}

} // namespace

void ask_cpu_driver_for_native_lanes() {
    // Once per process (function-local statics are initialized once, safely from several
    // threads); the environment itself is safe only before other threads start (the
    // header says where it is called).
    static const bool asked = [] {
        if (std::getenv(kWidthVariable) != nullptr || !cpu_has_avx512()) return false;
        return setenv(kWidthVariable, "512", /*overwrite=*/0) == 0;
    }();
    (void)asked;
}

} // namespace fird::vk
