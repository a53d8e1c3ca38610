// The workbench's tiling (ui/layout.hpp): panels fill the area at every size, never
// overlap or leave it, keep their proportions on a resize, keep their minimum where there
// is room, and a splitter moves exactly the two panels it separates.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "layout.hpp"
#include "settings.hpp"

namespace fird::ui {
namespace {

// Rounding the splits to whole pixels moves an edge by at most half a pixel each side.
constexpr float kPixel = 1.0f;

bool overlap(const PanelRect& a, const PanelRect& b) {
    return a.x < b.x + b.w && b.x < a.x + a.w && a.y < b.y + b.h && b.y < a.y + a.h;
}

// Every panel inside the area with a positive size, no two overlapping, and together
// they cover the area less the gaps (two column gaps and one row gap): nothing is lost.
void expect_tiles(const std::array<PanelRect, kPanelCount>& r, const PanelRect& area,
                  const LayoutMetrics& m) {
    double covered = 0.0;
    for (std::size_t i = 0; i < r.size(); ++i) {
        SCOPED_TRACE(panel_key(kPanels[i]));
        EXPECT_GT(r[i].w, 0.0f);
        EXPECT_GT(r[i].h, 0.0f);
        EXPECT_GE(r[i].x, area.x);
        EXPECT_GE(r[i].y, area.y);
        EXPECT_LE(r[i].x + r[i].w, area.x + area.w);
        EXPECT_LE(r[i].y + r[i].h, area.y + area.h);
        covered += double(r[i].w) * double(r[i].h);
        for (std::size_t j = i + 1; j < r.size(); ++j)
            EXPECT_FALSE(overlap(r[i], r[j])) << panel_key(kPanels[j]);
    }
    const double expected = (double(area.w) - 2.0 * m.gap_px) * (double(area.h) - m.gap_px);
    EXPECT_NEAR(covered, expected, 1e-6 * expected);
}

TEST(Layout, PanelsTileTheWindowAtEverySize) {
    const LayoutMetrics m;
    for (const auto& [w, h] : {std::pair{1600.0f, 1000.0f},
                               {1000.0f, 650.0f},
                               {640.0f, 360.0f},
                               {3840.0f, 2160.0f},
                               {321.0f, 243.0f}}) {
        SCOPED_TRACE(testing::Message() << w << " x " << h);
        const PanelRect area{0.0f, 19.0f, w, h - 19.0f};
        expect_tiles(tile(Layout{}, area, m), area, m);
        expect_tiles(tile(Layout{.left = 0.05, .right = 0.1, .row = 0.9}, area, m), area, m);
    }
}

TEST(Layout, ADamagedLayoutStillTilesTheWindow) {
    const LayoutMetrics m;
    const PanelRect area{0.0f, 0.0f, 1000.0f, 650.0f};
    for (const Layout& l : {Layout{.left = 2.0, .right = -1.0, .row = 5.0},
                            Layout{.left = std::nan(""), .right = 0.5, .row = 0.5},
                            Layout{.left = 0.7, .right = 0.2, .row = -3.0}})
        expect_tiles(tile(l, area, m), area, m);
}

TEST(Layout, ProportionsAreKeptOnResize) {
    const LayoutMetrics m;
    const Layout l{.left = 0.3, .right = 0.7, .row = 0.6};
    for (const float w : {1600.0f, 2400.0f, 1200.0f}) {
        const PanelRect area{0.0f, 0.0f, w, 1000.0f};
        const auto r = tile(l, area, m);
        const float tw = w - 2.0f * m.gap_px;
        EXPECT_NEAR(r[std::size_t(PanelId::Scene)].w, 0.3f * tw, kPixel) << w;
        EXPECT_NEAR(r[std::size_t(PanelId::Viewport)].w, 0.4f * tw, kPixel) << w;
        EXPECT_NEAR(r[std::size_t(PanelId::Scene)].h, 0.6f * (1000.0f - m.gap_px), kPixel) << w;
    }
}

TEST(Layout, APanelKeepsItsMinimumWhereThereIsRoom) {
    const LayoutMetrics m;
    const PanelRect area{0.0f, 0.0f, 1600.0f, 1000.0f};
    const auto r = tile(Layout{.left = 0.01, .right = 0.02, .row = 0.99}, area, m);
    for (const PanelRect& p : r) {
        EXPECT_GE(p.w, m.min_panel_w - kPixel);
        EXPECT_GE(p.h, m.min_panel_h - kPixel);
    }
    // No room for three minimum widths: they share the width, still tiling it.
    const PanelRect narrow{0.0f, 0.0f, 500.0f, 1000.0f};
    expect_tiles(tile(Layout{}, narrow, m), narrow, m);
}

TEST(Layout, ASplitterMovesOnlyThePanelsItSeparates) {
    const LayoutMetrics m;
    const PanelRect area{0.0f, 20.0f, 1600.0f, 980.0f};
    const Layout before;
    const auto r0 = tile(before, area, m);
    const auto r1 = tile(drag_splitter(before, Splitter::Left, 100.0f, area, m), area, m);
    const auto at = [](const auto& r, PanelId id) { return r[std::size_t(id)]; };
    EXPECT_NEAR(at(r1, PanelId::Scene).w, at(r0, PanelId::Scene).w + 100.0f, kPixel);
    EXPECT_NEAR(at(r1, PanelId::Viewport).w, at(r0, PanelId::Viewport).w - 100.0f, kPixel);
    EXPECT_NEAR(at(r1, PanelId::Viewport).x, at(r0, PanelId::Viewport).x + 100.0f, kPixel);
    EXPECT_EQ(at(r1, PanelId::FarField).x, at(r0, PanelId::FarField).x);
    EXPECT_EQ(at(r1, PanelId::FarField).w, at(r0, PanelId::FarField).w);
    EXPECT_EQ(at(r1, PanelId::Scene).h, at(r0, PanelId::Scene).h);
    // The row splitter moves the rows only.
    const auto r2 = tile(drag_splitter(before, Splitter::Row, -50.0f, area, m), area, m);
    EXPECT_NEAR(at(r2, PanelId::Viewport).h, at(r0, PanelId::Viewport).h - 50.0f, kPixel);
    EXPECT_NEAR(at(r2, PanelId::Optimize).y, at(r0, PanelId::Optimize).y - 50.0f, kPixel);
    EXPECT_EQ(at(r2, PanelId::Viewport).w, at(r0, PanelId::Viewport).w);
    // Dragged far past its neighbour, the splitter stops at the neighbour's minimum.
    const auto r3 = tile(drag_splitter(before, Splitter::Right, -5000.0f, area, m), area, m);
    EXPECT_GE(at(r3, PanelId::Viewport).w, m.min_panel_w - kPixel);
    expect_tiles(r3, area, m);
    // The splitter's grab area is the gap between the panels it separates.
    const PanelRect g = splitter_rect(before, Splitter::Left, area, m);
    EXPECT_EQ(g.x, at(r0, PanelId::Scene).x + at(r0, PanelId::Scene).w);
    EXPECT_EQ(g.x + g.w, at(r0, PanelId::Viewport).x);
}

// A saved layout is clamped when read: a hand-edited or damaged settings file cannot put
// a panel off-screen.
TEST(Layout, ASavedLayoutIsReadBackAndClamped) {
    const auto dir = std::filesystem::temp_directory_path() / "fird_layout_test";
    std::filesystem::create_directories(dir / "fird");
    ASSERT_EQ(setenv("XDG_CONFIG_HOME", dir.c_str(), 1), 0);
    Settings s;
    s.layout = {.left = 0.3, .right = 0.55, .row = 0.5};
    save_settings(s);
    const Settings back = load_settings();
    EXPECT_DOUBLE_EQ(back.layout.left, 0.3);
    EXPECT_DOUBLE_EQ(back.layout.right, 0.55);
    EXPECT_DOUBLE_EQ(back.layout.row, 0.5);
    std::ofstream(dir / "fird" / "settings.txt")
        << "layout_left=7\nlayout_right=-3\nlayout_row=nan\n";
    const Settings damaged = load_settings();
    const LayoutMetrics m;
    const PanelRect area{0.0f, 0.0f, 1000.0f, 650.0f};
    expect_tiles(tile(damaged.layout, area, m), area, m);
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace fird::ui
