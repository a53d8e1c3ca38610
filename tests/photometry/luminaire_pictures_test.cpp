// The luminaire pictures are written whole, each beside the desired one and the
// difference, at the size write_luminaire_views states; a pixel's readout is what is drawn
// there.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "candela_tables.hpp"
#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_pictures.hpp"
#include "plot/canvas.hpp"
#include "plot/colormap.hpp"

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

// The workbench's hover readout reads what is drawn under the pixel: over the polar map
// and the illuminance plane, every probed pixel whose colour is the map's (not a ring, a
// spoke, a label) has the colour of the value the readout gives there, on the drawing's
// scale (the obtained and desired share one: the larger peak, at nadir for these tables,
// I(0) in cd or I(0) / d^2 in lx). Each map is drawn from samples about a pixel apart, so
// a pixel's colour is its sample's, up to a pixel away: with these smooth tables that
// moves a colour by at most 6 of 255. The isocandela frame reads C 0-360 across and gamma
// 0-gamma_max down, and each panel reads its own table.
TEST(LuminaireReadout, ThePixelReadsTheValueDrawnThere) {
    // Lopsided in C (C60 brightest: no mirror of the C axes reads alike), falling with
    // gamma: a colour says where it is.
    std::vector<double> planes;
    for (int c = 0; c < 360; c += 5)
        planes.push_back(c);
    const CandelaTable obtained = test::formula_table(planes, [&](std::size_t k, double g) {
        return g <= 90.0 ? 800.0 * (0.6 + 0.4 * std::cos((planes[k] - 60.0) * kDeg)) * std::cos(g * kDeg)
                         : 0.0;
    });
    const CandelaTable desired = test::formula_table(
        {0.0}, [](std::size_t, double g) { return g <= 90.0 ? 600.0 * std::cos(g * kDeg) : 0.0; });
    const LuminaireViewOptions o{.title = "readout", .plane_distance_m = 2.0};
    const int w = 1500, h = 520;
    const plot::Rect area{0, 0, double(w), double(h)};
    const double gamma_max = luminaire_view_gamma_deg(obtained, &desired);
    for (const LuminaireView view : {LuminaireView::PolarMap, LuminaireView::Illuminance}) {
        SCOPED_TRACE(luminaire_view_name(view));
        plot::Canvas cv(w, h);
        draw_luminaire_view(cv, area, view, obtained, &desired, o);
        const auto rgba = cv.rgba();
        const bool plane = view == LuminaireView::Illuminance;
        const double peak = plane ? 800.0 / (o.plane_distance_m * o.plane_distance_m) : 800.0;
        int probed = 0, matched = 0;
        for (int y = 1; y < h; y += 15)
            for (int x = 1; x < w; x += 15) {
                const auto at = luminaire_view_readout(area, view, obtained, &desired, o, gamma_max,
                                                       x + 0.5, y + 0.5);
                if (!at || at->panel == LuminairePanel::Difference) continue;
                ASSERT_EQ(at->on_plane, plane);
                ASSERT_TRUE(at->desired);
                const double value =
                    at->panel == LuminairePanel::Obtained ? at->obtained : *at->desired;
                const plot::Rgb want = plot::sequential_colour(std::clamp(value / peak, 0.0, 1.0));
                const std::uint8_t* p = &rgba[(std::size_t(y) * w + std::size_t(x)) * 4];
                ++probed;
                int off = 0;
                for (int k = 0; k < 3; ++k)
                    off = std::max(off, std::abs(int(p[k]) - int(want[k])));
                // Lines and labels over the map are grey or ink: far from the colour.
                if (off <= 6) ++matched;
            }
        EXPECT_GT(probed, 500);
        EXPECT_GT(matched, 0.85 * probed) << matched << " of " << probed;
    }
    // Isocandela: the frame's top left reads C0 at nadir, its bottom right C360 at the
    // largest gamma shown; the values are each table's there.
    const auto iso = [&](double x, double y) {
        return luminaire_view_readout(area, LuminaireView::Isocandela, obtained, &desired, o,
                                      gamma_max, x, y);
    };
    int left = 0, top = 0; // the frame's first column across its middle, then its first row
    while (left < w && !iso(left + 0.5, h / 2.0))
        ++left;
    while (top < h && !iso(left + 0.5, top + 0.5))
        ++top;
    const auto first = iso(left + 0.5, top + 0.5);
    ASSERT_TRUE(first);
    EXPECT_NEAR(first->c_deg, 0.0, 1.0);
    EXPECT_NEAR(first->gamma_deg, 0.0, 1.0);
    EXPECT_NEAR(first->obtained, 640.0, 8.0); // 800 (0.6 + 0.4 cos 60 deg)
    EXPECT_NEAR(*first->desired, 600.0, 6.0);
    const auto mid = iso(w / 6.0, h / 2.0);
    ASSERT_TRUE(mid);
    EXPECT_EQ(mid->panel, LuminairePanel::Obtained);
    EXPECT_NEAR(mid->obtained, intensity_cd(obtained, mid->c_deg, mid->gamma_deg), 1e-9);
    const auto right = iso(w * 5.0 / 6.0, h / 2.0);
    ASSERT_TRUE(right);
    EXPECT_EQ(right->panel, LuminairePanel::Difference);
    EXPECT_GT(right->c_deg, mid->c_deg - 1e-9);
}

} // namespace
} // namespace fird
