// libFuzzer target: the OBJ and STL readers, and the height-field check over a holder,
// must refuse any input with an error naming the file, never crash or hang. The first
// byte picks the format.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "model/mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string name = data[0] % 2 ? "fuzz.obj" : "fuzz.stl";
    try {
        fird::TriangleMesh m = fird::parse_mesh(
            name, std::string(reinterpret_cast<const char*>(data + 1), size - 1), 1.0);
        if (m.triangles.size() > 200000) return 0; // bounded work per input
        const fird::Holder holder{{-10, -10, -10}, {10, 10, 10}};
        const fird::MeshHeightField field(std::move(m), holder, name);
        (void)field.height(0.5, -0.25);
        (void)field.bounds(-1, 1, -1, 1);
    } catch (const std::runtime_error&) {
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
