// libFuzzer target: the scene reader must refuse any input with a SceneError (naming the
// file, line and key), never crash, hang or accept NaN, Inf or an empty holder.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/scene_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const fird::Scene s =
            fird::parse_scene(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
        for (int k = 0; k < 3; ++k)
            if (!(s.holder.min_mm[k] < s.holder.max_mm[k]) || !std::isfinite(s.source.center_mm[k]))
                __builtin_trap(); // accepted a scene the reader must refuse
        (void)fird::parse_scene(fird::scene_to_toml(s), "fuzz.toml"); // and it round-trips
    } catch (const fird::SceneError&) {
    }
    return 0;
}
