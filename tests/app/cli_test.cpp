// The `fird` command's contract for bad input: one line, the usage, exit code 2.
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

struct Result {
    int code;
    std::string out;
};

Result run_env(const std::string& env, const std::string& args) {
    const std::string cmd = env + " " + std::string(FIRD_BINARY) + " " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, ""};
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe)) out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

Result run(const std::string& args) { return run_env("", args); }

TEST(Cli, UnknownSubcommandIsUsageErrorWithCode2) {
    const auto r = run("frobnicate");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("usage"), std::string::npos) << r.out;
}

TEST(Cli, UnknownOptionIsUsageErrorWithCode2) {
    const auto r = run("info --no-such-option");
    EXPECT_EQ(r.code, 2) << r.out;
}

TEST(Cli, NoSubcommandIsUsageError) { EXPECT_EQ(run("").code, 2); }

TEST(Cli, HelpExitsZero) { EXPECT_EQ(run("--help").code, 0); }

TEST(Cli, InfoJsonHasTheLimitsThatMatter) {
    const auto r = run("info --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["chosen"]["name"].get<std::string>().empty());
    for (const char* key : {"max_compute_workgroup_size", "max_compute_workgroup_count",
                            "max_storage_buffer_range", "subgroup_size", "float32_atomic_add",
                            "timestamps"})
        EXPECT_TRUE(j["limits"].contains(key)) << key;
}

TEST(Cli, UnknownDeviceNameExitsOneWithOneLine) {
    const auto r = run("--device no-such-gpu info");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no-such-gpu"), std::string::npos) << r.out;
}

TEST(Cli, NoVulkanDriverAtAllExitsOneWithOneLine) {
    // Point the loader at an empty driver list: no device at all.
    const auto r = run_env("VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json",
                           "info");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no Vulkan"), std::string::npos) << r.out;
}

} // namespace
