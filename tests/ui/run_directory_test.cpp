// The workbench's run folders (ui/run_directory.hpp): each run gets a new folder, and a
// folder that exists (an earlier run's, or one made by hand) is never reused.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "run_directory.hpp"

namespace fird::ui {
namespace {

TEST(RunDirectory, EachRunGetsANewFolderAndNoneIsReused) {
    namespace fs = std::filesystem;
    const fs::path base = fs::path(::testing::TempDir()) / "fird_run_directory_test";
    fs::remove_all(base);
    const std::string first = new_run_directory(base.string(), "model_a", "optimize");
    std::ofstream(fs::path(first) / "search.json") << "{}";
    // Made by hand in between: skipped, not written into.
    fs::create_directories(base / "model_a-optimize-2");
    const std::string second = new_run_directory(base.string(), "model_a", "optimize");
    EXPECT_EQ(fs::path(first).filename(), "model_a-optimize-1");
    EXPECT_EQ(fs::path(second).filename(), "model_a-optimize-3");
    EXPECT_TRUE(fs::path(second).is_absolute());
    EXPECT_TRUE(fs::is_empty(second));
    EXPECT_TRUE(fs::exists(fs::path(first) / "search.json")); // the earlier run is intact
    // Another job of the same scene counts on its own.
    EXPECT_EQ(fs::path(new_run_directory(base.string(), "model_a", "calibrate")).filename(),
              "model_a-calibrate-1");
    fs::remove_all(base);
}

TEST(RunDirectory, AFolderThatCannotBeCreatedIsAnErrorNamingIt) {
    namespace fs = std::filesystem;
    const fs::path file = fs::path(::testing::TempDir()) / "fird_run_directory_file";
    std::ofstream(file) << "not a folder";
    try {
        (void)new_run_directory((file / "runs").string(), "s", "optimize");
        FAIL() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
    }
    fs::remove(file);
}

} // namespace
} // namespace fird::ui
