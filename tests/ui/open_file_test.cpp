// Opening files in the workbench (ui/workbench_state.hpp): an IES or LDT file becomes the
// open scene's target by any route (not parsed as a scene), the scene panel's words name
// it, and the recent list keeps absolute paths.
#include <filesystem>

#include <gtest/gtest.h>

#include "workbench_state.hpp"

namespace fird::ui {
namespace {

const std::string kScene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";

TEST(OpenFile, AnIesFileBecomesTheTargetAndIsNamed) {
    WorkbenchState s;
    EXPECT_EQ(target_description(Scene{}), "none");
    ASSERT_TRUE(open_file(s, kScene)) << s.editor.error;
    EXPECT_NE(target_description(*s.editor.scene).find("sx = 0.15"), std::string::npos)
        << target_description(*s.editor.scene);
    for (const char* name : {"model_a_target.ies", "model_a_target.ldt"}) {
        const std::string path = std::string(FIRD_SOURCE_DIR) + "/scenes/targets/" + name;
        ASSERT_TRUE(open_file(s, path)) << s.editor.error;
        EXPECT_TRUE(s.editor.error.empty()) << s.editor.error;
        EXPECT_EQ(s.editor.scene->target.kind, TargetDesc::Kind::Photometric);
        EXPECT_EQ(s.editor.scene->target.resolved_path, path);
        EXPECT_EQ(target_description(*s.editor.scene).rfind(name, 0), 0u)
            << target_description(*s.editor.scene);
        EXPECT_EQ(s.editor.path, std::filesystem::path(kScene).lexically_normal().string())
            << "the scene stays open";
    }
}

TEST(OpenFile, ALuminaireFileWithoutASceneIsAnErrorNamingIt) {
    WorkbenchState s;
    const std::string path = std::string(FIRD_SOURCE_DIR) + "/scenes/targets/model_a_target.ies";
    EXPECT_FALSE(open_file(s, path));
    ASSERT_FALSE(s.log.empty());
    EXPECT_NE(s.log.back().find(path), std::string::npos) << s.log.back();
}

TEST(OpenFile, TheRecentListKeepsAbsolutePaths) {
    WorkbenchState s;
    const auto cwd = std::filesystem::current_path();
    std::filesystem::current_path(std::string(FIRD_SOURCE_DIR) + "/scenes");
    const bool opened = open_file(s, "test/mirror_search.toml");
    std::filesystem::current_path(cwd);
    ASSERT_TRUE(opened) << s.editor.error;
    ASSERT_FALSE(s.recent.empty());
    EXPECT_EQ(s.recent.front(), std::filesystem::path(kScene).lexically_normal().string());
}

} // namespace
} // namespace fird::ui
