// The workbench's tiling, as plain data and pure functions (no ImGui): six panels in
// three columns over two rows that always fill the window. The user moves the column and
// row splits; they are kept as fractions of the window, so proportions survive a resize,
// and a saved layout is clamped on load, so no layout can leave a panel off-screen.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace fird::ui {

enum class PanelId : std::size_t { Scene, Viewport, FarField, Log, Optimize, Calibrate };
constexpr std::size_t kPanelCount = 6;
constexpr std::array<PanelId, kPanelCount> kPanels = {PanelId::Scene,    PanelId::Viewport,
                                                      PanelId::FarField, PanelId::Log,
                                                      PanelId::Optimize, PanelId::Calibrate};

const char* panel_title(PanelId id); // the window's title ("Far field")
const char* panel_key(PanelId id);   // its name in --stats and tests ("far_field")

struct PanelRect {
    float x = 0, y = 0, w = 0, h = 0; // window pixels
};

// Where the splits are, as fractions of the area the panels tile.
struct Layout {
    double left = 0.24;  // the left column's right edge (scene, log)
    double right = 0.64; // the right column's left edge (far field, calibration)
    double row = 0.62;   // the top row's bottom edge
};

struct LayoutMetrics {
    float gap_px = 6.0f;        // between panels: where the splitters are grabbed
    float min_panel_w = 240.0f; // below these a panel's content scrolls (never overlaps)
    float min_panel_h = 150.0f;
};

enum class Splitter { Left, Right, Row };

// A layout with every split finite, inside the area and in order (what load and drag keep).
Layout clamped(Layout layout);

// The six panels' rectangles: they tile `area` exactly, separated by the gaps, none
// overlapping. Each panel gets at least the metrics' minimum where the area has room for
// all of them; otherwise they share the area in proportion (and their content scrolls).
std::array<PanelRect, kPanelCount> tile(const Layout& layout, const PanelRect& area,
                                        const LayoutMetrics& metrics);

// The splitter's grab area (in the gap between the panels it separates).
PanelRect splitter_rect(const Layout& layout, Splitter splitter, const PanelRect& area,
                        const LayoutMetrics& metrics);

// The layout after the splitter moved by delta_px (x for the column splits, y for the
// row split), kept so that no panel it borders goes below its minimum where there is room.
Layout drag_splitter(const Layout& layout, Splitter splitter, float delta_px, const PanelRect& area,
                     const LayoutMetrics& metrics);

} // namespace fird::ui
