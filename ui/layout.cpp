#include "layout.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace fird::ui {

namespace {

// Sizes for pieces that want `want` (summing to `total`): each at least `min` where
// there is room for all minimums, the shortfall taken from the others in proportion to
// their excess; without that room, the wants scaled to the total.
std::vector<float> fit(std::vector<float> want, float total, float min) {
    const float n = float(want.size());
    if (total <= n * min) {
        float sum = 0.0f;
        for (const float w : want)
            sum += std::max(0.0f, w);
        for (float& w : want)
            w = sum > 0.0f ? std::max(0.0f, w) * total / sum : total / n;
        return want;
    }
    float deficit = 0.0f, excess = 0.0f;
    for (float& w : want) {
        if (w < min)
            deficit += min - w, w = min;
        else
            excess += w - min;
    }
    // excess = total + deficit - n * min > deficit, so the scale is in [0, 1).
    const float keep = excess > 0.0f ? 1.0f - deficit / excess : 1.0f;
    for (float& w : want)
        if (w > min) w = min + (w - min) * keep;
    return want;
}

// Edges (start, end) of pieces of sizes `sizes` laid from `origin` with gaps, in whole
// pixels, the last ending exactly at `origin + extent`.
std::vector<std::pair<float, float>> edges(const std::vector<float>& sizes, float origin,
                                           float extent, float gap) {
    std::vector<std::pair<float, float>> e;
    float start = origin, at = origin;
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        at += sizes[i];
        const float end = i + 1 == sizes.size() ? origin + extent : std::round(at);
        e.emplace_back(start, std::max(start, end));
        start = e.back().second + gap;
        at += gap;
    }
    return e;
}

struct Tiling {
    std::vector<std::pair<float, float>> columns, rows;
};

Tiling tiling(const Layout& l, const PanelRect& area, const LayoutMetrics& m) {
    const float tw = std::max(0.0f, area.w - 2.0f * m.gap_px);
    const float th = std::max(0.0f, area.h - m.gap_px);
    const auto cols =
        fit({float(l.left) * tw, float(l.right - l.left) * tw, float(1.0 - l.right) * tw}, tw,
            m.min_panel_w);
    const auto rows = fit({float(l.row) * th, float(1.0 - l.row) * th}, th, m.min_panel_h);
    return {edges(cols, area.x, area.w, m.gap_px), edges(rows, area.y, area.h, m.gap_px)};
}

} // namespace

const char* panel_title(PanelId id) {
    constexpr std::array<const char*, kPanelCount> titles = {
        "Scene", "Viewport", "Far field", "Log", "Optimization", "Calibration"};
    return titles[std::size_t(id)];
}

const char* panel_key(PanelId id) {
    constexpr std::array<const char*, kPanelCount> keys = {"scene", "viewport", "far_field",
                                                           "log",   "optimize", "calibrate"};
    return keys[std::size_t(id)];
}

Layout clamped(Layout l) {
    const Layout d;
    if (!std::isfinite(l.left) || !std::isfinite(l.right) || !std::isfinite(l.row)) return d;
    l.left = std::clamp(l.left, 0.05, 0.85);
    l.right = std::clamp(l.right, l.left + 0.05, 0.95);
    l.row = std::clamp(l.row, 0.1, 0.9);
    return l;
}

std::array<PanelRect, kPanelCount> tile(const Layout& layout, const PanelRect& area,
                                        const LayoutMetrics& metrics) {
    const Tiling t = tiling(clamped(layout), area, metrics);
    std::array<PanelRect, kPanelCount> r;
    for (std::size_t row = 0; row < 2; ++row)
        for (std::size_t col = 0; col < 3; ++col) {
            const auto [x0, x1] = t.columns[col];
            const auto [y0, y1] = t.rows[row];
            r[row * 3 + col] = {x0, y0, x1 - x0, y1 - y0};
        }
    return r;
}

PanelRect splitter_rect(const Layout& layout, Splitter s, const PanelRect& area,
                        const LayoutMetrics& m) {
    const Tiling t = tiling(clamped(layout), area, m);
    switch (s) {
    case Splitter::Left:
        return {t.columns[0].second, area.y, m.gap_px, area.h};
    case Splitter::Right:
        return {t.columns[1].second, area.y, m.gap_px, area.h};
    case Splitter::Row:
        break;
    }
    return {area.x, t.rows[0].second, area.w, m.gap_px};
}

Layout drag_splitter(const Layout& layout, Splitter s, float delta_px, const PanelRect& area,
                     const LayoutMetrics& m) {
    Layout l = clamped(layout);
    const Tiling t = tiling(l, area, m);
    const double tw = std::max(1.0f, area.w - 2.0f * m.gap_px);
    const double th = std::max(1.0f, area.h - m.gap_px);
    // The minimum as a fraction, where the area has room for every panel's minimum.
    const double min_w = 3.0 * m.min_panel_w <= tw ? m.min_panel_w / tw : 0.05;
    const double min_h = 2.0 * m.min_panel_h <= th ? m.min_panel_h / th : 0.1;
    switch (s) {
    case Splitter::Left:
        l.left = std::clamp((t.columns[0].second + delta_px - area.x) / tw, min_w, l.right - min_w);
        break;
    case Splitter::Right:
        l.right = std::clamp((t.columns[1].second + delta_px - area.x - m.gap_px) / tw,
                             l.left + min_w, 1.0 - min_w);
        break;
    case Splitter::Row:
        l.row = std::clamp((t.rows[0].second + delta_px - area.y) / th, min_h, 1.0 - min_h);
        break;
    }
    return clamped(l);
}

} // namespace fird::ui
