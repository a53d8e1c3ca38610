// After the scripted windowed sessions (tests/ui/change_parameter.fird and
// change_source.fird, run under Xvfb by the fixture tests before this one): the far field
// the window shows changed with the parameter and with the source, and the scene panel did
// not move.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "image_regions.hpp"
#include "plot/canvas.hpp"

namespace fird::test {
namespace {

TEST(WindowedSession, AParameterChangeChangesTheFarFieldShown) {
    int wa = 0, ha = 0, wb = 0, hb = 0;
    const auto before = plot::read_png_rgba("ui_before.png", wa, ha);
    const auto after = plot::read_png_rgba("ui_after.png", wb, hb);
    ASSERT_EQ(wa, wb);
    ASSERT_EQ(ha, hb);
    // The far-field panel (right, top) changed; the log panel (left, bottom) did not.
    EXPECT_GT(region_difference(before, after, wa, ha, 0.66, 0.08, 0.99, 0.58), 2.0);
    EXPECT_LT(region_difference(before, after, wa, ha, 0.01, 0.70, 0.22, 0.99), 0.5);
}

// Each screenshot of a session (same size) shows another far field in the panel than the
// one before it.
void expect_each_far_field_changed(const std::vector<std::string>& shots) {
    int w0 = 0, h0 = 0;
    std::vector<std::uint8_t> before = plot::read_png_rgba(shots[0], w0, h0);
    for (std::size_t k = 1; k < shots.size(); ++k) {
        int w = 0, h = 0;
        std::vector<std::uint8_t> after = plot::read_png_rgba(shots[k], w, h);
        ASSERT_EQ(w, w0);
        ASSERT_EQ(h, h0);
        EXPECT_GT(region_difference(before, after, w0, h0, 0.66, 0.08, 0.99, 0.58), 2.0)
            << shots[k];
        before = std::move(after);
    }
}

// After tests/ui/change_source.fird: the LED die, a tilted disk and an IES file's
// distribution each give another far field in the panel.
TEST(WindowedSession, AChangedSourceChangesTheFarFieldShown) {
    expect_each_far_field_changed(
        {"ui_source_die.png", "ui_source_disk.png", "ui_source_photometric.png"});
}

// After tests/ui/change_material.fird: a spread lobe, then the direct light binned, each
// give another far field in the panel.
TEST(WindowedSession, AChangedMaterialChangesTheFarFieldShown) {
    expect_each_far_field_changed(
        {"ui_material_mirror.png", "ui_material_spread.png", "ui_material_direct.png"});
}

// The panel layout (its splits) is saved with the settings in the config directory when
// the session ends (after its last screenshot).
TEST(WindowedSession, ThePanelLayoutIsSavedInTheConfigDirectoryAtExit) {
    const std::filesystem::path settings =
        std::filesystem::path(FIRD_UI_CONFIG_DIR) / "fird/settings.txt";
    ASSERT_TRUE(std::filesystem::is_regular_file(settings)) << settings;
    EXPECT_GE(std::filesystem::last_write_time(settings),
              std::filesystem::last_write_time("ui_after.png"));
    std::ifstream in(settings);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (const char* key : {"layout_left=", "layout_right=", "layout_row="})
        EXPECT_NE(text.find(key), std::string::npos) << key;
}

} // namespace
} // namespace fird::test
