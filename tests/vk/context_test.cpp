// Device selection and error reporting of the Vulkan core.
#include <chrono>
#include <gtest/gtest.h>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/submission.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

TEST(Context, UnknownDeviceNameIsAClearError) {
    try {
        (void)vk::Context::create({.device_name = "no-such-device-xyz"});
        FAIL() << "expected NoDeviceError";
    } catch (const vk::NoDeviceError& e) {
        EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos) << e.what();
    }
}

TEST(Context, ChoosesAUsableDeviceAndReportsLimits) {
    const auto ctx = vk::Context::create({});
    EXPECT_TRUE(ctx.summary().usable);
    EXPECT_GE(ctx.limits().max_workgroup_invocations, 128u);
    EXPECT_GE(ctx.limits().max_storage_buffer_range, 1u << 27);
    EXPECT_GT(ctx.limits().subgroup_size, 0u);
}

TEST(Check, FailureNamesTheCallAndResult) {
    try {
        FIRD_VK_CHECK(VK_ERROR_OUT_OF_DEVICE_MEMORY);
        FAIL();
    } catch (const vk::VulkanError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos) << what;
        EXPECT_NE(what.find("out of device memory"), std::string::npos) << what;
    }
}

TEST_F(VulkanTest, ImpossibleAllocationIsAnErrorNotACrash) {
    // Far more than any device has: must come back as a VulkanError.
    EXPECT_THROW(vk::Buffer(ctx(), VkDeviceSize(1) << 50, vk::kStorageUsage, vk::MemoryUse::Device,
                            "test.too_big"),
                 vk::VulkanError);
}

TEST_F(VulkanTest, UploadDownloadRoundTrip) {
    std::vector<std::uint32_t> values(1000);
    for (std::uint32_t i = 0; i < values.size(); ++i)
        values[i] = i * 2654435761u;
    vk::Buffer b(ctx(), values.size() * 4, vk::kStorageUsage, vk::MemoryUse::Device, "test.rt");
    b.upload(ctx(), std::span<const std::uint32_t>(values));
    EXPECT_EQ(b.download_as<std::uint32_t>(ctx(), values.size()), values);
}

// A submission made while another is being recorded on the same thread (what a staging
// upload inside a frame's recording does on a device whose working memory is not
// host-visible, as on NVIDIA's driver): it runs in buffers of its own, its result is there
// when it returns, the outer recording goes on, and the validation layers report nothing
// (the fixture fails the test on any of their errors).
TEST_F(VulkanTest, ASubmissionFromInsideAnothersRecordingRunsOnItsOwn) {
    const std::vector<std::uint32_t> inner{1, 2, 3, 4}, outer{9, 8, 7, 6};
    vk::Buffer a(ctx(), 16, vk::kStorageUsage, vk::MemoryUse::Device, "test.nested.inner");
    vk::Buffer b(ctx(), 16, vk::kStorageUsage, vk::MemoryUse::Device, "test.nested.outer");
    b.upload(ctx(), std::span<const std::uint32_t>(outer));
    const std::uint64_t before = ctx().submissions();
    ctx().submit_and_wait([&](VkCommandBuffer cb) {
        ctx().submit_and_wait(
            [&](VkCommandBuffer inner_cb) { vkCmdFillBuffer(inner_cb, a.get(), 0, 16, 5u); });
        // The inner submission has finished: its fill is there before this one runs.
        EXPECT_EQ(a.download_as<std::uint32_t>(ctx(), 4), std::vector<std::uint32_t>(4, 5u));
        vkCmdFillBuffer(cb, b.get(), 0, 16, 11u);
    });
    EXPECT_EQ(b.download_as<std::uint32_t>(ctx(), 4), std::vector<std::uint32_t>(4, 11u));
    // And a second time, from the same thread: the nested buffers are made afresh.
    ctx().submit_and_wait(
        [&](VkCommandBuffer) { a.upload(ctx(), std::span<const std::uint32_t>(inner)); });
    EXPECT_EQ(a.download_as<std::uint32_t>(ctx(), 4), inner);
    EXPECT_GE(ctx().submissions() - before, 3u);
}

// A submission the host does not wait for: done() only polls, and once it says so (or
// wait() returns) what it wrote is there; a second one behind it on the queue sees the
// first's writes (the queue's submission order), and neither counts as a host round trip
// of submit_and_wait.
TEST_F(VulkanTest, ASubmissionRunsWithoutTheHostWaitingAndIsPolled) {
    vk::Buffer b(ctx(), 4096, vk::kStorageUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                 vk::MemoryUse::Readback, "test.submission");
    const std::uint64_t before = ctx().submissions();
    vk::Submission fill(
        ctx(), [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, b.get(), 0, 4096, 0x01020304u); },
        "test.fill");
    vk::Submission half(
        ctx(),
        [&](VkCommandBuffer cb) {
            vk::barrier_all(cb);
            vkCmdFillBuffer(cb, b.get(), 2048, 2048, 0x0a0b0c0du);
            vk::barrier_to_host(cb);
        },
        "test.fill_half");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!half.done())
        ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the submission never finished";
    fill.wait();
    const auto* words = static_cast<const std::uint32_t*>(b.data());
    for (std::size_t i = 0; i < 1024; ++i)
        ASSERT_EQ(words[i], i < 512 ? 0x01020304u : 0x0a0b0c0du) << "word " << i;
    EXPECT_EQ(ctx().submissions(), before);
    EXPECT_TRUE(vk::Submission().done()); // nothing submitted: nothing to wait for
}

// The worker's work gets a queue of its own exactly where the universal family has a
// second one (lavapipe has one queue, shared; discrete GPUs have 8-16), and what the work
// queue wrote is what a later submission on the frames' queue reads: the hand-over is a
// fence the host waited on.
TEST_F(VulkanTest, WorkGetsAQueueOfItsOwnWhereTheFamilyHasTwoAndHandsOverThroughTheHost) {
    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx().physical_device(), &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(ctx().physical_device(), &n, families.data());
    ASSERT_LT(ctx().queue_family(), n);
    EXPECT_EQ(ctx().separate_work_queue(), families[ctx().queue_family()].queueCount >= 2);

    const VkBufferUsageFlags usage =
        vk::kStorageUsage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    vk::Buffer written(ctx(), 1024, usage, vk::MemoryUse::Device, "test.work_queue.written");
    vk::Buffer read(ctx(), 1024, usage, vk::MemoryUse::Readback, "test.frames_queue.read");
    ctx().submit_and_wait(
        [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, written.get(), 0, 1024, 0x5a5a1234u); });
    const vk::Submission copy(
        ctx(),
        [&](VkCommandBuffer cb) {
            const VkBufferCopy region{.size = 1024};
            vkCmdCopyBuffer(cb, written.get(), read.get(), 1, &region);
            vk::barrier_to_host(cb);
        },
        "test.frames_queue.copy");
    copy.wait();
    const auto* words = static_cast<const std::uint32_t*>(read.data());
    for (std::size_t i = 0; i < 256; ++i)
        ASSERT_EQ(words[i], 0x5a5a1234u) << "word " << i;
}

} // namespace
} // namespace fird::test
