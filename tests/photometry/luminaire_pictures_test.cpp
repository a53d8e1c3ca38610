// The luminaire pictures are written whole, each beside the desired one and the
// difference, at the size write_luminaire_views states.
#include <cmath>
#include <filesystem>
#include <numbers>

#include <gtest/gtest.h>

#include "candela_tables.hpp"
#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_pictures.hpp"
#include "plot/canvas.hpp"

namespace fird {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using test::formula_table;

// The three pictures, each beside the desired one and the difference, written whole.
TEST(LuminaireViews, ThePicturesAreWrittenBesideTheDesiredOnes) {
    const CandelaTable beam = formula_table({0.0}, [](std::size_t, double g) {
        return g <= 90.0 ? 800.0 * std::pow(std::cos(g * kDeg), 4) : 0.0;
    });
    const CandelaTable wide = formula_table(
        {0.0}, [](std::size_t, double g) { return g <= 90.0 ? 500.0 * std::cos(g * kDeg) : 0.0; });
    const FarField a = farfield_from_table(beam, 360, 180), b = farfield_from_table(wide, 360, 180);
    const std::string dir = ::testing::TempDir() + "/fird_luminaire_views";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    write_luminaire_views(dir, a, &b, {.title = "beam", .plane_distance_m = 2.0});
    for (const char* name : {"polar.png", "isocandela.png", "illuminance.png"}) {
        int w = 0, h = 0;
        const auto rgba = plot::read_png_rgba(dir + "/" + name, w, h);
        EXPECT_EQ(w, 3 * 520) << name;
        EXPECT_GT(h, 400) << name;
    }
}

} // namespace
} // namespace fird
