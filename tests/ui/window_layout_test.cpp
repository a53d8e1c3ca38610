// After the windowed sessions run under Xvfb by the fixture tests before this one, each
// writing `fird gui --stats`: the panels tile the window at 1000 x 650 and again after it
// is restored to 1600 x 1000, a drag in the viewport orbits the camera without moving any
// panel, and a search run to its end leaves its best on the sliders. Each check runs on two
// sets of sessions: the scripted ones (tests/ui/*.fird: the workbench's own script actions)
// and the real-input ones (tests/ui/real_input_session.sh: xdotool's mouse and keyboard
// through the X server, as a user's hands).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "image_regions.hpp"
#include "io/scene_file.hpp"
#include "plot/canvas.hpp"

namespace fird::test {
namespace {

const char* const kPanels[] = {"scene", "viewport", "far_field", "log", "optimize", "calibrate"};

nlohmann::json read_stats(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    return nlohmann::json::parse(in);
}

// Every panel reported, inside the window, at least a title bar's size, none overlapping.
void expect_tiled(const nlohmann::json& stats, double w, double h) {
    ASSERT_EQ(stats.at("window").at(0).get<double>(), w);
    ASSERT_EQ(stats.at("window").at(1).get<double>(), h);
    const auto& panels = stats.at("panels");
    for (const char* a : kPanels) {
        SCOPED_TRACE(a);
        ASSERT_TRUE(panels.contains(a));
        const auto r = panels.at(a).get<std::vector<double>>();
        ASSERT_EQ(r.size(), 4u);
        EXPECT_GE(r[0], 0.0);
        EXPECT_GE(r[1], 0.0);
        EXPECT_LE(r[0] + r[2], w);
        EXPECT_LE(r[1] + r[3], h);
        EXPECT_GE(r[2], 100.0); // a usable panel: wider and taller than a title bar
        EXPECT_GE(r[3], 60.0);
        for (const char* b : kPanels) {
            if (std::string(a) >= std::string(b)) continue;
            const auto q = panels.at(b).get<std::vector<double>>();
            const bool overlap = r[0] < q[0] + q[2] && q[0] < r[0] + r[2] && r[1] < q[1] + q[3] &&
                                 q[1] < r[1] + r[3];
            EXPECT_FALSE(overlap) << a << " overlaps " << b;
        }
    }
}

// One set of sessions: its stats files' prefix and the search's data folder.
struct Sessions {
    std::string prefix;      // <prefix>_small.json, _restored.json, _dragged.json
    std::string search;      // the search session's stats
    std::string search_data; // its XDG_DATA_HOME
};

class WindowLayout : public testing::TestWithParam<Sessions> {
  protected:
    nlohmann::json stats(const char* session) const {
        return read_stats(GetParam().prefix + "_" + session + ".json");
    }
};

INSTANTIATE_TEST_SUITE_P(
    Input, WindowLayout,
    testing::Values(Sessions{"layout", "search_stats.json", FIRD_UI_DATA_DIR "/data"},
                    Sessions{"real", "real_search.json", FIRD_UI_DATA_DIR "/session/data_search"}),
    [](const testing::TestParamInfo<Sessions>& i) {
        return i.param.prefix == "real" ? std::string("Xdotool") : std::string("Scripted");
    });

TEST_P(WindowLayout, PanelsTileTheShrunkWindow) {
    expect_tiled(stats("small"), 1000, 650);
}

TEST_P(WindowLayout, PanelsTileTheWindowRestoredAfterShrinking) {
    const auto restored = stats("restored");
    expect_tiled(restored, 1600, 1000);
    // And they use it: the panels cover most of the window (gaps and the menu bar aside).
    double covered = 0.0;
    for (const char* a : kPanels) {
        const auto r = restored.at("panels").at(a).get<std::vector<double>>();
        covered += r[2] * r[3];
    }
    EXPECT_GT(covered, 0.95 * 1600 * 1000);
}

TEST_P(WindowLayout, ADragInTheViewportOrbitsTheCameraAndMovesNoPanel) {
    const auto still = stats("restored");
    const auto dragged = stats("dragged");
    expect_tiled(dragged, 1600, 1000);
    EXPECT_EQ(dragged.at("panels"), still.at("panels"));
    // 120 px right and 40 px down at the documented 0.4 deg per pixel (docs/workbench.md):
    // the azimuth turns by -48 deg and the elevation rises by 16 deg; the tolerance covers
    // the float sum of ten mouse moves.
    const auto& c0 = still.at("camera");
    const auto& c1 = dragged.at("camera");
    EXPECT_NEAR(c1.at("azimuth_deg").get<double>() - c0.at("azimuth_deg").get<double>(), -48.0,
                0.01);
    EXPECT_NEAR(c1.at("elevation_deg").get<double>() - c0.at("elevation_deg").get<double>(), 16.0,
                0.01);
    EXPECT_EQ(c1.at("distance_mm"), c0.at("distance_mm")); // a drag neither zooms
    EXPECT_EQ(c1.at("target_mm"), c0.at("target_mm"));     // nor pans
}

// tests/ui/drag_splitter.fird: a drag on the gap between the scene and viewport columns
// moves that split by the drag's 100 px and nothing else (the row, the far-field column,
// the camera).
TEST(WindowLayout, ADragOnASplitterMovesOnlyThePanelsItSeparates) {
    const auto still = read_stats("layout_restored.json");
    const auto moved = read_stats("layout_splitter.json");
    expect_tiled(moved, 1600, 1000);
    const auto rect = [](const nlohmann::json& stats, const char* panel) {
        return stats.at("panels").at(panel).get<std::vector<double>>();
    };
    // Whole pixels: the split is rounded to a pixel after the move.
    for (const char* left : {"scene", "log"}) {
        EXPECT_NEAR(rect(moved, left)[2], rect(still, left)[2] + 100.0, 1.0) << left;
        EXPECT_EQ(rect(moved, left)[3], rect(still, left)[3]) << left;
    }
    for (const char* middle : {"viewport", "optimize"}) {
        EXPECT_NEAR(rect(moved, middle)[0], rect(still, middle)[0] + 100.0, 1.0) << middle;
        EXPECT_NEAR(rect(moved, middle)[2], rect(still, middle)[2] - 100.0, 1.0) << middle;
    }
    for (const char* right : {"far_field", "calibrate"})
        EXPECT_EQ(rect(moved, right), rect(still, right)) << right;
    EXPECT_EQ(moved.at("camera"), still.at("camera"));
}

// tests/ui/search_to_the_end.fird: the mirror scene's search, run to its end in the
// window, leaves its best on the sliders: the parameters the search wrote to its run
// folder (the first under the test's data directory), which are the scene's analytic
// optimum (sx 0.15, sy -0.1, on the step lattice) within one step (0.05): the scene's own
// promise for every method.
TEST_P(WindowLayout, ASearchRunToTheEndPutsItsBestOnTheSliders) {
    const auto stats = read_stats(GetParam().search);
    std::ifstream in(GetParam().search_data + "/fird/runs/mirror_search-optimize-1/search.json");
    ASSERT_TRUE(in);
    const auto search = nlohmann::json::parse(in);
    const auto& best = search.at("best_parameters");
    const auto& sliders = stats.at("parameters");
    ASSERT_FALSE(best.empty());
    for (const auto& [name, value] : best.items())
        EXPECT_EQ(sliders.at(name).get<double>(), value.get<double>()) << name;
    EXPECT_NEAR(sliders.at("sx").get<double>(), 0.15, 0.05);
    EXPECT_NEAR(sliders.at("sy").get<double>(), -0.1, 0.05);
    EXPECT_NE(search.at("stopped").get<std::string>(), "interrupted");
    // Its folder holds what a command's does as it goes, to be followed (fird follow): the
    // options it began with and a history row for every candidate search.json counts.
    const std::string folder = GetParam().search_data + "/fird/runs/mirror_search-optimize-1";
    std::ifstream options_in(folder + "/options.json");
    ASSERT_TRUE(options_in);
    EXPECT_EQ(nlohmann::json::parse(options_in).at("method"), search.at("method"));
    std::ifstream history(folder + "/history.csv");
    std::size_t lines = 0;
    for (std::string line; std::getline(history, line);)
        ++lines;
    EXPECT_EQ(lines, search.at("evaluations").get<std::size_t>() + 1); // and the header
}

// tests/ui/search_then_switch.fird: the flat mirror opened while the mirror scene's search
// runs keeps its own parameters (scenes/test/flat_mirror.toml: sx 0.2, sy -0.1, z0 -2)
// when that search ends (its best, sx 0.15 on the lattice, belongs to the other scene),
// and the search still finished and wrote its files.
TEST(WindowSearch, ASearchEndingAfterASceneSwitchLeavesTheNewSceneAlone) {
    const auto stats = read_stats("switch_stats.json");
    const auto& sliders = stats.at("parameters");
    EXPECT_EQ(sliders.at("sx").get<double>(), 0.2);
    EXPECT_EQ(sliders.at("sy").get<double>(), -0.1);
    EXPECT_EQ(sliders.at("z0").get<double>(), -2.0);
    std::ifstream in(FIRD_UI_DATA_DIR
                     "/data_switch/fird/runs/mirror_search-optimize-1/search.json");
    EXPECT_TRUE(in) << "the search's files";
}

// tests/ui/follow_folder.fird: a search started outside the window (the test's shell, into
// followed/) and followed from its folder to its end: its best, as its own search.json
// states it, went on the sliders of the open scene it searches; the job written after
// holds the scene as shown (sx moved to 0.05, sy the best's) and scripts that start it, and
// the window then followed the job's folder, where no search has begun yet.
TEST(FollowedFolder, ItsBestGoesOnTheSlidersAndAJobHoldsTheSceneAsShown) {
    const auto stats = read_stats("follow_stats.json");
    std::ifstream in("followed/search.json");
    ASSERT_TRUE(in);
    const auto search = nlohmann::json::parse(in);
    const auto& best = search.at("best_parameters");
    EXPECT_EQ(stats.at("parameters").at("sy"), best.at("sy"));
    EXPECT_EQ(stats.at("parameters").at("sx").get<double>(), 0.05);
    const auto& job = stats.at("job");
    const Scene scene = load_scene(job.at("scene").get<std::string>());
    EXPECT_EQ(scene.reflector.parameters.at("sx"), 0.05);
    EXPECT_EQ(scene.reflector.parameters.at("sy"), best.at("sy").get<double>());
    EXPECT_TRUE(std::filesystem::exists(job.at("run_sh").get<std::string>()));
    EXPECT_TRUE(std::filesystem::exists(job.at("slurm_sh").get<std::string>()));
    const auto& follow = stats.at("follow");
    EXPECT_EQ(std::filesystem::path(follow.at("dir").get<std::string>()),
              std::filesystem::path(job.at("scene").get<std::string>()).parent_path());
    EXPECT_FALSE(follow.at("began").get<bool>());
}

// tests/ui/tailored_search.fird: the optimize panel's tailored start began the search at the
// tailored profile (search.json's start, as fird optimize --start tailored records it: its
// kind, an edge ray, a start metric traced) and its best went on the sliders.
TEST(TailoredStart, TheWindowsSearchBeginsAtTheTailoredProfile) {
    const auto stats = read_stats("tailored_stats.json");
    std::ifstream in(std::string(FIRD_UI_DATA_DIR) +
                     "/data_tailored/fird/runs/profile_search-optimize-1/search.json");
    ASSERT_TRUE(in);
    const auto search = nlohmann::json::parse(in);
    const auto& start = search.at("start");
    EXPECT_EQ(start.at("kind"), "tailored");
    EXPECT_TRUE(start.at("edge_ray") == "crossing" || start.at("edge_ray") == "diverging") << start;
    EXPECT_TRUE(start.at("metric_at_start").is_number()) << start;
    EXPECT_EQ(search.at("method"), "cmaes");
    for (const auto& [name, value] : search.at("best_parameters").items())
        EXPECT_EQ(stats.at("parameters").at(name).get<double>(), value.get<double>()) << name;
}

// tests/ui/freeform_search.fird: auto on nine free heights ran to its end in the window
// (hundreds of candidates on its charts, more vertices in one window than 16-bit indices
// reach), CMA-ES's run first as the command runs it, and its best went on the sliders.
TEST(FreeformSearch, TheWindowsAutoSearchRunsToItsEndWithItsBestOnTheSliders) {
    const auto stats = read_stats("freeform_stats.json");
    std::ifstream in(std::string(FIRD_UI_DATA_DIR) +
                     "/data_freeform/fird/runs/freeform_search-optimize-1/search.json");
    ASSERT_TRUE(in);
    const auto search = nlohmann::json::parse(in);
    EXPECT_EQ(search.at("method"), "auto");
    EXPECT_EQ(search.at("stopped"), "converged");
    const auto& runs = search.at("population").at("runs");
    ASSERT_FALSE(runs.empty());
    EXPECT_EQ(runs.at(0).at("method"), "cmaes");
    // Hundreds of candidates, each a dot on ten charts (16 vertices each): past 65,536.
    EXPECT_GT(search.at("evaluations").get<int>(), 500);
    ASSERT_EQ(search.at("best_parameters").size(), 9u);
    for (const auto& [name, value] : search.at("best_parameters").items())
        EXPECT_EQ(stats.at("parameters").at(name).get<double>(), value.get<double>()) << name;
}

// The rows of a tolerance.csv, each split at its commas, the header first.
std::vector<std::vector<std::string>> csv_rows(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ',');)
            cells.push_back(cell);
        rows.push_back(cells);
    }
    return rows;
}

// tests/ui/tolerance_session.fird: the calibrate panel's tolerance form, filled as fird
// tolerance's options are given, traces the realisations the command traces. Each row's
// draws come from the counter-based generator on (seed, realisation), so they must be the
// same text; the measures come from the same rays traced on the same device at one vector
// width (tests/CMakeLists.txt sets it for both), where the window submits at most 131072
// rays at a time (docs/workbench.md): the far field's counts do not depend on it, so the
// measures agree to the 9 digits written.
TEST(ToleranceInTheWindow, TracesTheRealisationsTheCommandTraces) {
    const auto stats = read_stats("tolerance_stats.json");
    const auto& t = stats.at("tolerance");
    EXPECT_TRUE(t.at("ended").get<bool>()) << t;
    EXPECT_FALSE(t.at("stopped").get<bool>()) << t;
    // The nominal luminaire, then 4 joint realisations and 4 for each of the three tolerances.
    EXPECT_EQ(t.at("traced").get<int>(), 1 + 4 * 4) << t;
    const auto window = csv_rows(t.at("dir").get<std::string>() + "/tolerance.csv");
    const auto command = csv_rows("tolerance_cli/tolerance.csv");
    ASSERT_EQ(window.size(), 1u + 1 + 4 * 4);
    ASSERT_EQ(window.size(), command.size());
    EXPECT_EQ(window[0], command[0]); // the header
    for (std::size_t r = 1; r < window.size(); ++r) {
        SCOPED_TRACE("row " + std::to_string(r) + ": " + window[r][0]);
        ASSERT_EQ(window[r].size(), command[r].size());
        for (std::size_t c = 0; c < window[r].size(); ++c)
            EXPECT_EQ(window[r][c], command[r][c]) << command[0][c];
    }
    std::ifstream json(t.at("dir").get<std::string>() + "/tolerance.json");
    ASSERT_TRUE(json);
    EXPECT_TRUE(std::filesystem::exists(t.at("dir").get<std::string>() + "/tolerance.png"));
}

// tests/ui/cad_session.fird: the scene panel's CAD section writes, for the reflector the
// sliders show, the files fird export --cad writes for the same parameters and options
// (one function behind both): the STL byte for byte, the STEP file from its DATA section
// on (its header holds the time it was written).
TEST(CadInTheWindow, WritesTheFilesTheCommandWrites) {
    const auto stats = read_stats("cad_stats.json");
    const auto& c = stats.at("cad");
    ASSERT_TRUE(c.is_object()) << stats;
    EXPECT_EQ(c.at("dir").get<std::string>(), "cad_window");
    EXPECT_TRUE(c.at("creased").get<bool>());
    EXPECT_EQ(c.at("bend_radius_mm").get<double>(), 1.0) << "twice the sheet";
    const auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        EXPECT_TRUE(in) << path;
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string stl = bytes("cad_window/reflector.stl");
    EXPECT_GT(stl.size(), 84u);
    EXPECT_TRUE(stl == bytes("cad_cli/reflector.stl")) << "the STL files differ";
    const auto data = [&](const std::string& path) {
        const std::string step = bytes(path);
        const auto at = step.find("DATA;");
        EXPECT_NE(at, std::string::npos) << path;
        return at == std::string::npos ? std::string() : step.substr(at);
    };
    const std::string window = data("cad_window/reflector.step");
    EXPECT_GT(window.size(), 1000u);
    EXPECT_TRUE(window == data("cad_cli/reflector.step")) << "the STEP files' data differ";
}

// tests/ui/offscreen_session.fird, run with no display (fird gui --offscreen 1600x1000): the
// far field drawn changed with the parameter and the log did not (as in the windowed
// session), the resize gave frames of the new size, the panels tile them exactly as they
// tile the windowed session's window at that size, and nothing was saved.
TEST(OffscreenSession, DrawsTheWorkbenchWithNoDisplayAsTheWindowDoes) {
    const auto stats = read_stats("offscreen_stats.json");
    EXPECT_TRUE(stats.at("offscreen").get<bool>());
    EXPECT_GT(stats.at("frames").get<int>(), 5);
    // Every frame was drawn into the image but the one built before the resize (whose
    // size the new image no longer has).
    EXPECT_GE(stats.at("frames_drawn").get<int>(), stats.at("frames").get<int>() - 1);
    expect_tiled(stats, 1000, 650);
    EXPECT_EQ(stats.at("panels"), read_stats("layout_small.json").at("panels"));

    int wa = 0, ha = 0, wb = 0, hb = 0, ws = 0, hs = 0;
    const auto before = plot::read_png_rgba("offscreen_before.png", wa, ha);
    const auto after = plot::read_png_rgba("offscreen_after.png", wb, hb);
    plot::read_png_rgba("offscreen_small.png", ws, hs);
    EXPECT_EQ(wa, 1600);
    EXPECT_EQ(ha, 1000);
    ASSERT_EQ(wb, wa);
    ASSERT_EQ(hb, ha);
    EXPECT_EQ(ws, 1000);
    EXPECT_EQ(hs, 650);
    // The far-field panel (right, top) and the log panel (left, bottom), as in
    // WindowedSession.AParameterChangeChangesTheFarFieldShown.
    EXPECT_GT(region_difference(before, after, wa, ha, 0.66, 0.08, 0.99, 0.58), 2.0);
    EXPECT_LT(region_difference(before, after, wa, ha, 0.01, 0.70, 0.22, 0.99), 0.5);
    // An offscreen session leaves the user's settings alone.
    EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(FIRD_UI_OFFSCREEN_CONFIG_DIR) /
                                         "fird/settings.txt"));
}

} // namespace
} // namespace fird::test
