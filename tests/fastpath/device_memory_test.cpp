// How many vkAllocateMemory calls one evaluation makes (issue 24: buffers are ranges of a
// few shared blocks, not an allocation each).
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>

#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "vk/buffer.hpp"
#include "vk/context.hpp"

namespace fird::test {
namespace {

// The memory types besides the device-local one that buffers use (none on lavapipe, whose
// one type is everything; a discrete GPU's host-visible types for uploads and readbacks):
// each holds a few small buffers, one block's worth, on top of the device-local blocks.
std::uint64_t other_memory_types(const vk::Context& ctx) {
    // Asked of the device without a buffer: making one would allocate a block.
    const VkBufferCreateInfo buffer{.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                    .size = 4,
                                    .usage = vk::kStorageUsage,
                                    .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    const VkDeviceBufferMemoryRequirements info{
        .sType = VK_STRUCTURE_TYPE_DEVICE_BUFFER_MEMORY_REQUIREMENTS, .pCreateInfo = &buffer};
    VkMemoryRequirements2 got{.sType = VK_STRUCTURE_TYPE_MEMORY_REQUIREMENTS_2};
    vkGetDeviceBufferMemoryRequirements(ctx.device(), &info, &got);
    const VkMemoryRequirements& req = got.memoryRequirements;
    const auto host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    const std::set<std::uint32_t> types{
        ctx.find_memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT),
        ctx.find_memory_type(req.memoryTypeBits, host, 0),
        ctx.find_memory_type(req.memoryTypeBits, host, VK_MEMORY_PROPERTY_HOST_CACHED_BIT)};
    return types.size() - 1;
}

// Model A at 1e4 rays, with its target (a second evaluator traces the desired far field
// while the first is alive). No buffer is over half a 64 MiB block (the largest are the
// 1200 x 800 gradients, 7.7 MB, and the 1800 x 900 far fields, 6.5 MB), so none gets
// memory of its own; the two tracers and the compare hold about 90 MB in all (per
// tracer: two far fields 13 MB, two quadtrees 10.2 MB, gradients 7.7 MB, corners 3.8 MB,
// rays 0.6 MB; the desired far field 6.5 MB), which two 64 MiB blocks hold with a third
// for the holes first fit leaves (and one block for each other memory type used). Before the
// blocks, every buffer was an allocation of its own: 47 for Model A's evaluation at its 1e7 rays.
TEST(DeviceMemory, ModelAAtFewRaysTakesAFewBlocks) {
    const vk::Context ctx = vk::Context::create({.validation = true});
    Scene scene = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/model_a.toml");
    scene.trace.rays = 10000;
    const std::uint64_t others = other_memory_types(ctx);
    const auto before = ctx.memory_allocations();
    const Evaluation e = evaluate_fast(ctx, scene, {.profile = true});
    const auto after = ctx.memory_allocations();
    ASSERT_TRUE(e.device_memory_allocations.has_value());
    EXPECT_EQ(*e.device_memory_allocations, after.total - before.total);
    EXPECT_GE(after.total - before.total, 2u) << "90 MB do not fit one 64 MiB block";
    EXPECT_LE(after.total - before.total, 3u + others);
    EXPECT_EQ(e.tally.emitted,
              e.tally.discarded + e.tally.direct + e.tally.farfield + e.tally.lost);
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

} // namespace
} // namespace fird::test
