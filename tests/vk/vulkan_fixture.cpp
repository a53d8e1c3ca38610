#include "vulkan_fixture.hpp"

namespace fird::test {

std::unique_ptr<vk::Context> VulkanTest::context_;

void VulkanTest::SetUpTestSuite() {
    if (!context_)
        context_ = std::make_unique<vk::Context>(vk::Context::create({.validation = true}));
}

void VulkanTest::TearDownTestSuite() {
    context_.reset();
}

void VulkanTest::SetUp() {
    errors_before_ = context_->validation_errors();
}

void VulkanTest::TearDown() {
    EXPECT_EQ(context_->validation_errors(), errors_before_)
        << "Vulkan validation errors were reported during this test (see stderr)";
}

} // namespace fird::test
