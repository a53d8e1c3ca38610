#pragma once
// A test process's scratch directory, for the files a test writes and reads back.
//
// One per process under the test temp dir, named for the process (CTest runs each test case
// as a process of its own, so two cases running at once never share one). It is removed
// when the process's tests have passed and kept where one failed, to be looked at: before,
// every run left its exports behind (3 GB of CAD and VTK outputs in /tmp after a few days
// of runs).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

namespace fird::test {

class ScratchDir : public ::testing::Environment {
  public:
    explicit ScratchDir(const std::string& prefix)
        : path_(std::filesystem::path(::testing::TempDir()) /
                (prefix + "." + std::to_string(::getpid()))) {}
    // Made when the tests start, not when the binary starts (CTest's discovery runs it to
    // list the tests, and no TearDown follows a listing). One that cannot be made fails the
    // run (GoogleTest then runs no test) rather than throwing where nothing would catch it.
    void SetUp() override {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
        if (!ec) std::filesystem::create_directories(path_, ec);
        if (ec) GTEST_FAIL() << "scratch directory " << path_ << ": " << ec.message();
    }
    // (Under --gtest_repeat, Passed() is the last repetition's.)
    void TearDown() override {
        std::error_code ec;
        if (::testing::UnitTest::GetInstance()->Passed()) std::filesystem::remove_all(path_, ec);
    }
    // `name` inside the directory, with nothing there yet.
    std::string fresh(const std::string& name) const {
        const std::filesystem::path p = path_ / name;
        std::filesystem::remove_all(p);
        return p.string();
    }

  private:
    std::filesystem::path path_;
};

// Registers the process's scratch directory with GoogleTest (which owns it).
inline const ScratchDir& add_scratch_dir(const std::string& prefix) {
    return *static_cast<const ScratchDir*>(
        ::testing::AddGlobalTestEnvironment(new ScratchDir(prefix)));
}

} // namespace fird::test
