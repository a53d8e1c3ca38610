// The luminaire pictures are written whole, each beside the desired one and the
// difference, at the size write_luminaire_views states.
#include <cmath>
#include <filesystem>
#include <numbers>

#include <gtest/gtest.h>

#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_pictures.hpp"
#include "plot/canvas.hpp"

namespace fird {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A type C table of planes `planes_deg` (each constant in C between them, as
// intensity_cd interpolates) with intensity cd(c index, gamma) every degree of gamma.
template <class Cd> CandelaTable table(const std::vector<double>& planes_deg, const Cd& cd) {
    CandelaTable t;
    t.c_deg = planes_deg;
    for (int g = 0; g <= 180; ++g)
        t.gamma_deg.push_back(g);
    for (std::size_t c = 0; c < planes_deg.size(); ++c)
        for (int g = 0; g <= 180; ++g)
            t.cd.push_back(cd(c, double(g)));
    return t;
}

// The three pictures, each beside the desired one and the difference, written whole.
TEST(LuminaireViews, ThePicturesAreWrittenBesideTheDesiredOnes) {
    const CandelaTable beam = table({0.0}, [](std::size_t, double g) {
        return g <= 90.0 ? 800.0 * std::pow(std::cos(g * kDeg), 4) : 0.0;
    });
    const CandelaTable wide = table(
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
