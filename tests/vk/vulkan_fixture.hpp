// A test fixture that owns one Vulkan context with validation layers on (when
// installed) and fails the test if any validation error was reported during it.
#pragma once

#include <cstdint>
#include <memory>

#include <gtest/gtest.h>

#include "vk/context.hpp"

namespace fird::test {

class VulkanTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite();
    static void TearDownTestSuite();
    void SetUp() override;
    void TearDown() override;
    static const vk::Context& ctx() { return *context_; }

  private:
    static std::unique_ptr<vk::Context> context_;
    std::uint64_t errors_before_ = 0;
};

} // namespace fird::test
