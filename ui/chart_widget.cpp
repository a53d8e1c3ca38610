#include "chart_widget.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace fird::ui {

namespace {

// A point within this many pixels of the mouse is the one the readout names.
constexpr double kHoverPx = 8.0;
// The most points one ImDrawList::AddPolyline is given (draw_series): 4 vertices a point at
// most, so 8192 points stay far below the 65,536 vertices of one 16-bit-indexed piece.
constexpr std::size_t kPolylinePoints = 8192;

ImU32 with_alpha(ImU32 c, float alpha) {
    ImVec4 v = ImGui::ColorConvertU32ToFloat4(c);
    v.w *= alpha;
    return ImGui::GetColorU32(v);
}

// A chart colour on the UI's dark background: ink becomes the text colour, the palette's
// colours are lifted a little towards white so thin lines stay visible.
ImU32 ui_colour(const plot::Colour& c, float alpha = 1.0f) {
    const double luminance = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    if (luminance < 0.25) return with_alpha(ImGui::GetColorU32(ImGuiCol_Text), alpha);
    const auto lift = [](double v) { return float(0.8 * v + 0.2); };
    return ImGui::GetColorU32(ImVec4(lift(c.r), lift(c.g), lift(c.b), float(c.a) * alpha));
}

void dashed_line(ImDrawList* dl, ImVec2 a, ImVec2 b, ImU32 colour, float width) {
    const float dx = b.x - a.x, dy = b.y - a.y, length = std::hypot(dx, dy);
    constexpr float kDash = 6.0f, kSpace = 4.0f;
    for (float t = 0.0f; t < length; t += kDash + kSpace) {
        const float u0 = t / length, u1 = std::min(length, t + kDash) / length;
        dl->AddLine(ImVec2(a.x + dx * u0, a.y + dy * u0), ImVec2(a.x + dx * u1, a.y + dy * u1),
                    colour, width);
    }
}

void draw_series(ImDrawList* dl, const plot::Chart& c, const plot::Series& s,
                 const plot::AxisMapping& mx, const plot::AxisMapping& my) {
    const std::size_t n = std::min(s.x.size(), s.y.size());
    const auto at = [&](double x, double y) { return ImVec2(float(mx(x)), float(my(y))); };
    const auto shown = [&](double x, double y) {
        return std::isfinite(x) && std::isfinite(y) &&
               (c.x.scale == plot::Scale::Linear || x > 0) &&
               (c.y.scale == plot::Scale::Linear || y > 0);
    };
    if (s.kind == plot::Series::Kind::Band) {
        // One quad per step (a band's edges are monotone in x: each quad is convex).
        const ImU32 fill = ui_colour(s.colour, 0.25f);
        for (std::size_t i = 0; i + 1 < std::min(n, s.y_upper.size()); ++i)
            if (shown(s.x[i], s.y[i]) && shown(s.x[i + 1], s.y[i + 1]) &&
                shown(s.x[i], s.y_upper[i]) && shown(s.x[i + 1], s.y_upper[i + 1]))
                dl->AddQuadFilled(at(s.x[i], s.y[i]), at(s.x[i + 1], s.y[i + 1]),
                                  at(s.x[i + 1], s.y_upper[i + 1]), at(s.x[i], s.y_upper[i]), fill);
        return;
    }
    const ImU32 colour = ui_colour(s.colour);
    if (s.kind == plot::Series::Kind::Points) {
        for (std::size_t i = 0; i < n; ++i)
            if (shown(s.x[i], s.y[i]))
                dl->AddCircleFilled(at(s.x[i], s.y[i]),
                                    float(i < s.radius_px.size() ? s.radius_px[i] : 3.5), colour,
                                    8);
        return;
    }
    // Lines break at values the axis cannot show (NaN, or <= 0 on a log axis).
    std::vector<ImVec2> run;
    const auto flush = [&] {
        if (s.dashed)
            for (std::size_t i = 1; i < run.size(); ++i)
                dashed_line(dl, run[i - 1], run[i], colour, float(s.width));
        else
            // In pieces of at most kPolylinePoints, each starting where the last ended: ImGui
            // splits a draw list at 16-bit indices' 65,536 vertices only between primitives,
            // and one polyline past the bound wraps its indices (wrong triangles drawn); an
            // anti-aliased polyline takes up to 4 vertices a point, and a stage's best-so-far
            // line has a point per candidate (100,000 for a long CMA-ES search).
            for (std::size_t first = 0; first + 1 < run.size(); first += kPolylinePoints - 1)
                dl->AddPolyline(run.data() + first,
                                int(std::min(kPolylinePoints, run.size() - first)), colour, 0,
                                float(s.width));
        run.clear();
    };
    for (std::size_t i = 0; i < n; ++i)
        if (shown(s.x[i], s.y[i]))
            run.push_back(at(s.x[i], s.y[i]));
        else
            flush();
    flush();
}

// The legend: a swatch and the label of each named series, in rows that wrap at the width.
// Returns the height used.
float draw_legend(ImDrawList* dl, const plot::Chart& c, ImVec2 origin, float width) {
    const float line = ImGui::GetTextLineHeight(), swatch = line * 1.2f, gap = line * 0.8f;
    float x = origin.x, y = origin.y;
    bool any = false;
    for (const plot::Series& s : c.series) {
        if (s.label.empty()) continue;
        const float w = swatch + 4.0f + ImGui::CalcTextSize(s.label.c_str()).x;
        if (any && x + w > origin.x + width) x = origin.x, y += line;
        const ImU32 colour = ui_colour(s.colour);
        const float mid = y + 0.5f * line;
        if (s.kind == plot::Series::Kind::Points)
            dl->AddCircleFilled(ImVec2(x + 0.5f * swatch, mid), 0.3f * line, colour, 10);
        else if (s.kind == plot::Series::Kind::Band)
            dl->AddRectFilled(ImVec2(x, mid - 0.3f * line), ImVec2(x + swatch, mid + 0.3f * line),
                              ui_colour(s.colour, 0.35f));
        else
            dl->AddLine(ImVec2(x, mid), ImVec2(x + swatch, mid), colour, float(s.width));
        dl->AddText(ImVec2(x + swatch + 4.0f, y), ImGui::GetColorU32(ImGuiCol_Text),
                    s.label.c_str());
        x += w + gap;
        any = true;
    }
    return any ? y + line - origin.y : 0.0f;
}

std::string readout_value(double v) {
    return fmt::format("{:.5g}", v);
}

} // namespace

void chart_widget(const char* id, const plot::Chart& c, ImVec2 size) {
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    size.x = std::max(size.x, 1.0f), size.y = std::max(size.y, 1.0f);
    ImGui::InvisibleButton(id, size);
    const bool hovered = ImGui::IsItemHovered();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(origin, ImVec2(origin.x + size.x, origin.y + size.y), true);
    const float line = ImGui::GetTextLineHeight();
    const ImU32 text = ImGui::GetColorU32(ImGuiCol_Text);
    const ImU32 dim = ImGui::GetColorU32(ImGuiCol_TextDisabled);

    // Rows above the plot: the title, the legend, the y axis's label (written across, above
    // its axis, so it is never cut however short the chart is).
    float top = origin.y;
    if (!c.title.empty()) {
        dl->AddText(ImVec2(origin.x, top), text, c.title.c_str());
        top += line;
    }
    if (c.legend) top += draw_legend(dl, c, ImVec2(origin.x, top), size.x);
    if (!c.y.label.empty() && c.y.label != c.title) {
        dl->AddText(ImVec2(origin.x, top), dim, c.y.label.c_str());
        top += line;
    }
    top += 0.5f * line; // the top tick's label is centred on it
    // Rows below: the x ticks' labels and the x axis's label.
    const float bottom = origin.y + size.y - line * (c.x.label.empty() ? 1.2f : 2.2f);
    const auto [x0, x1] = plot::axis_limits(c, false);
    const auto [y0, y1] = plot::axis_limits(c, true);
    plot::AxisMapping my{c.y.scale, y0, y1, bottom, top};
    const auto height = [&](const std::string&) { return double(line); };
    const auto yticks = plot::axis_ticks(my, height, 0.5 * line);
    float label_w = 0.0f;
    for (const plot::Tick& t : yticks)
        label_w = std::max(label_w, ImGui::CalcTextSize(t.label.c_str()).x);
    const float left = origin.x + label_w + 8.0f;
    const float right = origin.x + size.x - 0.5f * ImGui::CalcTextSize("00000").x;
    plot::AxisMapping mx{c.x.scale, x0, x1, left, right};
    const auto width = [&](const std::string& s) {
        return double(ImGui::CalcTextSize(s.c_str()).x);
    };
    const auto xticks = plot::axis_ticks(mx, width, line);

    if (bottom - top >= 4.0f && right - left >= 4.0f) {
        dl->AddRectFilled(ImVec2(left, top), ImVec2(right, bottom),
                          ImGui::GetColorU32(ImGuiCol_FrameBg));
        const ImU32 grid = with_alpha(text, 0.12f);
        for (const plot::Tick& t : yticks) {
            const float y = float(my(t.value));
            dl->AddLine(ImVec2(left, y), ImVec2(right, y), grid);
            const ImVec2 ts = ImGui::CalcTextSize(t.label.c_str());
            dl->AddText(ImVec2(left - 5.0f - ts.x, y - 0.5f * ts.y), text, t.label.c_str());
        }
        for (const plot::Tick& t : xticks) {
            const float x = float(mx(t.value));
            dl->AddLine(ImVec2(x, top), ImVec2(x, bottom), grid);
            const ImVec2 ts = ImGui::CalcTextSize(t.label.c_str());
            dl->AddText(ImVec2(x - 0.5f * ts.x, bottom + 0.1f * line), text, t.label.c_str());
        }
        if (!c.x.label.empty()) {
            const ImVec2 ts = ImGui::CalcTextSize(c.x.label.c_str());
            dl->AddText(ImVec2(0.5f * (left + right - ts.x), bottom + 1.1f * line), dim,
                        c.x.label.c_str());
        }
        dl->PushClipRect(ImVec2(left, top), ImVec2(right, bottom), true);
        for (const plot::Series& s : c.series)
            draw_series(dl, c, s, mx, my);
        // Horizontal marks' labels, right-aligned: one that would cover an earlier one (two
        // marks at nearly one value, as a final l2 at the noise floor) goes under its line.
        std::vector<std::pair<float, float>> placed;
        const auto free_at = [&](float from, float to) {
            return std::none_of(placed.begin(), placed.end(),
                                [&](const auto& p) { return from < p.second && p.first < to; });
        };
        for (const plot::Mark& m : c.marks) {
            const ImU32 colour = ui_colour(m.colour);
            if (m.vertical && mx.inside(m.value)) {
                const float x = float(mx(m.value));
                dashed_line(dl, ImVec2(x, top), ImVec2(x, bottom), colour, 1.3f);
                dl->AddText(ImVec2(x + 4.0f, top), colour, m.label.c_str());
            } else if (!m.vertical && my.inside(m.value)) {
                const float y = float(my(m.value));
                dashed_line(dl, ImVec2(left, y), ImVec2(right, y), colour, 1.3f);
                const ImVec2 ts = ImGui::CalcTextSize(m.label.c_str());
                const float label_y = free_at(y - ts.y, y) ? y - ts.y : y + 1.0f;
                placed.emplace_back(label_y, label_y + ts.y);
                dl->AddText(ImVec2(right - 4.0f - ts.x, label_y), colour, m.label.c_str());
            }
        }
        dl->PopClipRect();
        dl->AddRect(ImVec2(left, top), ImVec2(right, bottom), with_alpha(text, 0.5f));
    }
    dl->PopClipRect();

    if (!hovered) return;
    const ImVec2 mouse = ImGui::GetIO().MousePos;
    const auto name = [](const plot::Axis& a, const char* fallback) {
        return a.label.empty() ? std::string(fallback) : a.label;
    };
    if (const auto near = plot::nearest_point(c, mx, my, mouse.x, mouse.y, kHoverPx)) {
        const plot::Series& s = c.series[near->series];
        const double x = s.x[near->index], y = s.y[near->index];
        dl->AddCircle(ImVec2(float(mx(x)), float(my(y))), 5.0f, text, 12, 1.5f);
        ImGui::SetTooltip("%s\n%s: %s\n%s: %s", s.label.empty() ? c.title.c_str() : s.label.c_str(),
                          name(c.x, "x").c_str(), readout_value(x).c_str(), name(c.y, "y").c_str(),
                          readout_value(y).c_str());
    } else if (mouse.x >= left && mouse.x <= right && mouse.y >= top && mouse.y <= bottom) {
        ImGui::SetTooltip("%s: %s\n%s: %s", name(c.x, "x").c_str(),
                          readout_value(mx.value_at(mouse.x)).c_str(), name(c.y, "y").c_str(),
                          readout_value(my.value_at(mouse.y)).c_str());
    }
}

} // namespace fird::ui
