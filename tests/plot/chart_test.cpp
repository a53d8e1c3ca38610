// The axis logic both chart renderers share (compute/plot/chart.hpp): tick labels that never
// overlap however small the axis, a constant series shown about its value, the hover
// readout's nearest point; the search progress charts' parameter axes; and the far field's
// zoom window on the brightest rows.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "optimize/search_report.hpp"
#include "plot/chart.hpp"
#include "plot/farfield_picture.hpp"

namespace fird::test {
namespace {

// A label's extent as a UI font of 7 px per character (13 px high) would measure it.
double width_px(const std::string& s) {
    return 7.0 * double(s.size());
}
double height_px(const std::string&) {
    return 13.0;
}

// Neighbouring labels' boxes (centred on their ticks) keep at least the gap apart.
void expect_apart(const plot::AxisMapping& m, const std::vector<plot::Tick>& ticks,
                  double (*extent)(const std::string&), double gap) {
    for (std::size_t i = 1; i < ticks.size(); ++i) {
        const double apart = std::abs(m(ticks[i].value) - m(ticks[i - 1].value));
        EXPECT_GE(apart, 0.5 * (extent(ticks[i].label) + extent(ticks[i - 1].label)) + gap)
            << ticks[i - 1].label << " and " << ticks[i].label << " over " << std::abs(m.p1 - m.p0)
            << " px";
    }
}

TEST(ChartAxis, TickLabelsNeverOverlapAtAnySize) {
    const std::pair<double, double> ranges[] = {{0, 1},   {-0.0123, 0.0456}, {11.4, 12.6},
                                                {0, 174}, {-1e6, 3e6},       {1e-7, 3e-7}};
    for (const auto& [lo, hi] : ranges)
        for (double length : {12.0, 30.0, 55.0, 80.0, 110.0, 200.0, 400.0, 900.0}) {
            const plot::AxisMapping x{plot::Scale::Linear, lo, hi, 0.0, length};
            const auto xt = plot::axis_ticks(x, width_px, 13.0);
            ASSERT_FALSE(xt.empty());
            expect_apart(x, xt, width_px, 13.0);
            const plot::AxisMapping y{plot::Scale::Linear, lo, hi, length, 0.0};
            const auto yt = plot::axis_ticks(y, height_px, 6.5);
            ASSERT_FALSE(yt.empty());
            expect_apart(y, yt, height_px, 6.5);
            for (const plot::Tick& t : yt)
                EXPECT_TRUE(y.inside(t.value)) << t.label;
            // Room for several labels gives several: the budget is used, not just one tick.
            if (length >= 200.0) {
                EXPECT_GE(yt.size(), 3u) << lo << ".." << hi;
            }
        }
    for (double length : {20.0, 60.0, 150.0, 600.0}) {
        const plot::AxisMapping y{plot::Scale::Log, 1e-6, 1e6, length, 0.0};
        const auto yt = plot::axis_ticks(y, height_px, 6.5);
        ASSERT_FALSE(yt.empty());
        expect_apart(y, yt, height_px, 6.5);
    }
    // A linear axis of 0..1 over 600 px: the round steps of 0.2 (six labels, the most).
    const plot::AxisMapping wide{plot::Scale::Linear, 0.0, 1.0, 0.0, 600.0};
    const auto t = plot::axis_ticks(wide, width_px, 13.0);
    ASSERT_EQ(t.size(), 6u);
    EXPECT_EQ(t[1].label, "0.2");
}

TEST(ChartAxis, AConstantSeriesIsShownAboutItsValue) {
    plot::Chart c;
    c.series.push_back({.x = {3.0}, .y = {0.0}});
    // About 0: ±1 (a sliver of ±1e-9 made every tick read 0 or 1e-9).
    auto [lo, hi] = plot::axis_limits(c, true);
    EXPECT_DOUBLE_EQ(lo, -1.0);
    EXPECT_DOUBLE_EQ(hi, 1.0);
    // Elsewhere: ±5 % of the value.
    c.series[0].y = {12.0, 12.0};
    std::tie(lo, hi) = plot::axis_limits(c, true);
    EXPECT_NEAR(lo, 11.4, 1e-12);
    EXPECT_NEAR(hi, 12.6, 1e-12);
    // The axis's fixed limits win over the data.
    c.y.min = 5.0, c.y.max = 20.0;
    std::tie(lo, hi) = plot::axis_limits(c, true);
    EXPECT_EQ(lo, 5.0);
    EXPECT_EQ(hi, 20.0);
    // One fixed limit above all the data: still a range, on the fixed side.
    c.y.min = 30.0, c.y.max.reset();
    std::tie(lo, hi) = plot::axis_limits(c, true);
    EXPECT_EQ(lo, 30.0);
    EXPECT_GT(hi, lo);
}

TEST(ChartHover, TheNearestDrawnPointWithinReachIsNamed) {
    plot::Chart c{.y = {"l2", plot::Scale::Log}};
    c.series.push_back({.kind = plot::Series::Kind::Points, .x = {0, 1, 2}, .y = {1, 10, 100}});
    c.series.push_back({.x = {0, 2}, .y = {0.0, 50.0}}); // 0 is not drawn on a log axis
    c.series.push_back(
        {.kind = plot::Series::Kind::Band, .x = {0, 2}, .y = {1, 1}, .y_upper = {100, 100}});
    // x 0..2 over 0..200 px; y 1..100 over 100..0 px (a decade per 50 px).
    const plot::AxisMapping x{plot::Scale::Linear, 0, 2, 0, 200};
    const plot::AxisMapping y{plot::Scale::Log, 1, 100, 100, 0};
    // (1, 10) is drawn at (100, 50).
    auto near = plot::nearest_point(c, x, y, 103, 46, 8);
    ASSERT_TRUE(near);
    EXPECT_EQ(near->series, 0u);
    EXPECT_EQ(near->index, 1u);
    EXPECT_NEAR(near->distance_px, 5.0, 1e-9);
    // (2, 50) of the line is at (200, 50 - 50 log10(5) / ... ): y(50) = 100 - 50 log10(50).
    near = plot::nearest_point(c, x, y, 198, 100 - 50 * std::log10(50.0) + 1, 8);
    ASSERT_TRUE(near);
    EXPECT_EQ(near->series, 1u);
    EXPECT_EQ(near->index, 1u);
    // The line's (0, 0) is not drawn: at (0, 100) the points' (0, 1) is what is there.
    near = plot::nearest_point(c, x, y, 0, 100, 8);
    ASSERT_TRUE(near);
    EXPECT_EQ(near->series, 0u);
    EXPECT_EQ(near->index, 0u);
    // Nothing within reach (the band is not a point).
    EXPECT_FALSE(plot::nearest_point(c, x, y, 150, 20, 8));
}

TEST(ProgressCharts, ParameterAxesSpanTheSearchBoxFromTheFirstEvaluation) {
    SearchResult r;
    r.method = "auto";
    r.names = {"fx", "z0"};
    r.bounds = {{5.0, 20.0}, {-15.0, -5.0}};
    r.stages = {StageSummary{.name = "explore"}};
    r.history = {Candidate{.index = 0, .stage = 0, .x = {13.0, -10.0}, .l2_lm = 3.4, .score = 3.4}};
    const ProgressCharts charts = progress_charts(r);
    ASSERT_EQ(charts.parameters.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
        const auto [lo, hi] = plot::axis_limits(charts.parameters[k], true);
        EXPECT_LE(lo, r.bounds[k].first);
        EXPECT_GE(hi, r.bounds[k].second);
        // No more than the box and a margin of a tenth of it.
        EXPECT_GE(lo, r.bounds[k].first - 0.1 * (r.bounds[k].second - r.bounds[k].first));
        EXPECT_LE(hi, r.bounds[k].second + 0.1 * (r.bounds[k].second - r.bounds[k].first));
    }
    // Evaluations from 0 over whole numbers.
    const auto [x0, x1] = plot::axis_limits(charts.l2, false);
    EXPECT_EQ(x0, 0.0);
    EXPECT_GE(x1, 10.0);
}

// A population search's progress chart shades each generation's spread: the 10 % to the
// 90 % quantile of its feasible candidates' scores (linear between order statistics: of
// six sorted scores s0..s5, (s0 + s1) / 2 and (s4 + s5) / 2), flat from its first to its
// last row; the start (no generation) and a generation of one feasible score get none,
// and a search whose candidates carry no generation (a grid) has no band.
TEST(ProgressCharts, APopulationSearchShadesEachGenerationsSpread) {
    SearchResult r;
    r.method = "cmaes";
    r.names = {"a", "b"};
    r.stages = {StageSummary{.name = "explore"}};
    std::uint64_t index = 0;
    const auto add = [&](std::optional<std::uint32_t> generation, double score,
                         bool feasible = true) {
        r.history.push_back({.index = index++,
                             .stage = 0,
                             .x = {0.0, 0.0},
                             .feasible = feasible,
                             .l2_lm = feasible ? score : NAN,
                             .score = feasible ? score : NAN,
                             .generation = generation});
    };
    add(std::nullopt, 20.0); // the start, alone
    // Generation 1: 10, 1, 9, an infeasible candidate, 2, 8, 3 (rows 1 to 7).
    for (const double v : {10.0, 1.0, 9.0})
        add(1, v);
    add(1, 0.0, false);
    for (const double v : {2.0, 8.0, 3.0})
        add(1, v);
    // Generation 2: 5, 4.5, 4, 6, 5.5, 4.2 (rows 8 to 13); generation 3: one candidate.
    for (const double v : {5.0, 4.5, 4.0, 6.0, 5.5, 4.2})
        add(2, v);
    add(3, 3.0);
    const auto band_of = [](const ProgressCharts& c) -> const plot::Series* {
        for (const plot::Series& s : c.l2.series)
            if (s.kind == plot::Series::Kind::Band) return &s;
        return nullptr;
    };
    const ProgressCharts charts = progress_charts(r);
    const plot::Series* band = band_of(charts);
    ASSERT_NE(band, nullptr);
    EXPECT_EQ(band->x, (std::vector<double>{1.0, 7.0, 8.0, 13.0}));
    // Generation 1 sorted: 1 2 3 8 9 10; generation 2: 4 4.2 4.5 5 5.5 6.
    EXPECT_EQ(band->y, (std::vector<double>{1.5, 1.5, 4.1, 4.1}));
    EXPECT_EQ(band->y_upper, (std::vector<double>{9.5, 9.5, 5.75, 5.75}));
    for (Candidate& c : r.history)
        c.generation.reset();
    EXPECT_EQ(band_of(progress_charts(r)), nullptr);
}

// A zoomed far field looks at its brightest rows: a bright band at altitude 30..40 deg and a
// little stray light at -60 deg stretch the lit band from about -62 to 42 deg; its middle
// (-10 deg) is dark. A window of 20 deg must hold the bright band.
TEST(FarFieldZoom, TheWindowCentresOnTheBrightestRows) {
    const std::uint32_t W = 36, H = 180; // one row per degree
    FarField f{W, H, std::vector<double>(std::size_t(W) * H, 0.0)};
    const auto row = [&](double alt) { return std::uint32_t(90.0 - alt); };
    for (double alt = 31; alt <= 40; ++alt)
        for (std::uint32_t c = 0; c < W; ++c)
            f.lm[std::size_t(row(alt)) * W + c] = 1.0;
    for (std::uint32_t c = 0; c < W; ++c)
        f.lm[std::size_t(row(-59)) * W + c] = 0.01; // stray: 1 % of the band's rows' light
    const auto profiles = plot::light_profiles(f);
    const auto band = plot::lit_altitude_band(profiles);
    ASSERT_LT(band.second, -55.0); // the stray light is inside the lit band
    const auto [hi, lo] = plot::brightest_altitude_window(profiles, band, 20.0);
    EXPECT_NEAR(hi - lo, 20.0, 1e-9);
    EXPECT_GE(hi, 40.0);
    EXPECT_LE(lo, 30.0);
    // A window as tall as the band is the band.
    const auto whole = plot::brightest_altitude_window(profiles, band, band.first - band.second);
    EXPECT_EQ(whole, band);
}

// Across as down: a beam between azimuths 40 and 60 deg with stray light at -120 deg; the
// lit azimuth band reaches the stray light, a zoomed window of 40 deg holds the beam.
TEST(FarFieldZoom, TheAzimuthWindowCentresOnTheBrightestColumns) {
    const std::uint32_t W = 360, H = 18; // one column per degree
    FarField f{W, H, std::vector<double>(std::size_t(W) * H, 0.0)};
    const auto column = [&](double az) { return std::uint32_t(az + 180.0); };
    for (double az = 40; az < 60; ++az)
        for (std::uint32_t r = 0; r < H; ++r)
            f.lm[std::size_t(r) * W + column(az)] = 1.0;
    for (std::uint32_t r = 0; r < H; ++r)
        f.lm[std::size_t(r) * W + column(-120)] = 0.02; // 0.1 % of the beam's light
    const auto profiles = plot::light_profiles(f);
    const auto band = plot::lit_azimuth_band(profiles);
    ASSERT_LT(band.first, -120.0); // the stray light is inside the lit band
    ASSERT_GT(band.second, 60.0);
    const auto [left, right] = plot::brightest_azimuth_window(profiles, band, 40.0);
    EXPECT_NEAR(right - left, 40.0, 1e-9);
    EXPECT_LE(left, 40.0);
    EXPECT_GE(right, 60.0);
    // Light all round: the band is the whole circle.
    FarField round{W, H, std::vector<double>(std::size_t(W) * H, 1.0)};
    EXPECT_EQ(plot::lit_azimuth_band(plot::light_profiles(round)), std::make_pair(-180.0, 180.0));
}

} // namespace
} // namespace fird::test
