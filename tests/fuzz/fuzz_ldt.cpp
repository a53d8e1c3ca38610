// libFuzzer target: the EULUMDAT reader must refuse any input with a PhotometryError, never
// crash, hang or allocate without bound.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "photometry/ldt_reader.hpp"
#include "photometry/photometry_text.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const fird::CandelaTable t = fird::read_ldt_bytes(
            "fuzz.ldt", std::string_view(reinterpret_cast<const char*>(data), size));
        (void)fird::integrated_flux_lm(t);
        (void)fird::intensity_cd(t, 33.0, 44.0);
    } catch (const fird::PhotometryError&) {
    }
    return 0;
}
