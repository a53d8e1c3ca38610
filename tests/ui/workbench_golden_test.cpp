// The whole workbench frame, drawn offscreen (as `fird screenshot --view workbench`), at
// three window sizes against golden images (tests/ui/golden; the tolerance is
// golden_image.hpp's). The scene is copied to a fixed folder and the run folder set there
// (tests/CMakeLists.txt), so that no path that differs between checkouts is in the frame.
#include <filesystem>

#include <gtest/gtest.h>

#include "golden_image.hpp"
#include "workbench.hpp"

namespace fird::test {
namespace {

namespace fs = std::filesystem;

struct Size {
    int w, h;
};

class WorkbenchFrame : public testing::TestWithParam<Size> {};

TEST_P(WorkbenchFrame, MatchesItsGolden) {
    const auto [w, h] = GetParam();
    // A folder per size: the sizes' tests may run at once.
    const fs::path folder =
        fs::path(FIRD_UI_GOLDEN_SCENE_DIR) / (std::to_string(w) + "x" + std::to_string(h));
    fs::create_directories(folder);
    const fs::path scene = folder / "mirror_search.toml";
    fs::copy_file(fs::path(FIRD_SOURCE_DIR) / "scenes/test/mirror_search.toml", scene,
                  fs::copy_options::overwrite_existing);
    std::uint64_t errors = 0;
    const auto rgba = ui::render_workbench_offscreen("", true, scene.string(), std::uint32_t(w),
                                                     std::uint32_t(h), &errors);
    EXPECT_EQ(errors, 0u) << "Vulkan validation errors";
    ASSERT_EQ(rgba.size(), std::size_t(w) * std::size_t(h) * 4);
    expect_like_golden(rgba, w, h,
                       (fs::path(FIRD_SOURCE_DIR) / "tests/ui/golden" /
                        ("workbench_" + std::to_string(w) + "x" + std::to_string(h) + ".png"))
                           .string(),
                       Drawn::OnDevice);
}

// The smallest window the layout is checked at, the default, and a large desktop's.
INSTANTIATE_TEST_SUITE_P(Sizes, WorkbenchFrame,
                         testing::Values(Size{1000, 650}, Size{1600, 1000}, Size{1920, 1200}),
                         [](const testing::TestParamInfo<Size>& i) {
                             return std::to_string(i.param.w) + "x" + std::to_string(i.param.h);
                         });

} // namespace
} // namespace fird::test
