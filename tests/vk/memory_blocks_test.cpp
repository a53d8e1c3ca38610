// FIRD's block allocator (compute/vk/memory_blocks.hpp): the free list alone, checked
// against a byte map of what is taken, then buffers through a context of their own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/memory_blocks.hpp"

namespace fird::test {
namespace {

constexpr VkDeviceSize kMiB = VkDeviceSize(1) << 20;

// Random takes and gives back, each checked against a map of the bytes taken (the answer
// does not come from BlockRanges): a taken range lies on free bytes, aligned, and the
// free bytes are the block less what is taken.
TEST(BlockRanges, RangesNeverOverlapAreAlignedAndAllComeBackAsOne) {
    constexpr VkDeviceSize kSize = 1 << 16;
    vk::BlockRanges ranges(kSize);
    std::vector<bool> taken(kSize, false);
    VkDeviceSize taken_bytes = 0;
    std::map<VkDeviceSize, VkDeviceSize> live; // offset -> size
    std::mt19937 rng(7);
    std::size_t takes = 0;
    for (int step = 0; step < 4000; ++step) {
        const bool give = !live.empty() && (rng() % 3 == 0 || live.size() > 40);
        if (give) {
            auto it = live.begin();
            std::advance(it, rng() % live.size());
            ranges.give_back(it->first, it->second);
            for (VkDeviceSize b = it->first; b < it->first + it->second; ++b)
                taken[b] = false;
            taken_bytes -= it->second;
            live.erase(it);
        } else {
            const VkDeviceSize size = 1 + rng() % 3000;
            const VkDeviceSize alignment = VkDeviceSize(1) << (rng() % 9);
            const auto at = ranges.take(size, alignment);
            if (!at) continue; // full for now
            ++takes;
            ASSERT_EQ(*at % alignment, 0u);
            ASSERT_LE(*at + size, kSize);
            for (VkDeviceSize b = *at; b < *at + size; ++b) {
                ASSERT_FALSE(taken[b]) << "byte " << b << " handed out twice";
                taken[b] = true;
            }
            taken_bytes += size;
            live[*at] = size;
        }
        ASSERT_EQ(ranges.free_bytes(), kSize - taken_bytes);
    }
    EXPECT_GT(takes, 1000u);
    for (const auto& [offset, size] : live)
        ranges.give_back(offset, size);
    EXPECT_TRUE(ranges.unused());
    EXPECT_EQ(ranges.free_ranges(), 1u); // every neighbour joined again
}

TEST(BlockRanges, AFreedRangeIsJoinedToItsNeighboursAndReused) {
    vk::BlockRanges ranges(1000);
    const auto a = ranges.take(100, 1);
    const auto b = ranges.take(100, 1);
    const auto c = ranges.take(100, 1);
    ASSERT_TRUE(a && b && c);
    EXPECT_EQ(*a, 0u);
    EXPECT_EQ(*b, 100u);
    EXPECT_EQ(*c, 200u);
    EXPECT_EQ(ranges.free_ranges(), 1u); // [300, 1000)
    ranges.give_back(*a, 100);
    ranges.give_back(*c, 100); // joins the tail: [0, 100) and [200, 1000)
    EXPECT_EQ(ranges.free_ranges(), 2u);
    EXPECT_EQ(ranges.take(80, 1), std::optional<VkDeviceSize>(0)); // first fit: a's hole
    ranges.give_back(0, 80);
    ranges.give_back(*b, 100); // [0, 1000) again
    EXPECT_EQ(ranges.free_ranges(), 1u);
    EXPECT_EQ(ranges.take(1000, 1), std::optional<VkDeviceSize>(0));
    EXPECT_EQ(ranges.take(1, 1), std::nullopt);
}

TEST(BlockRanges, AlignmentPaddingStaysFree) {
    vk::BlockRanges ranges(4096);
    ASSERT_EQ(ranges.take(10, 1), std::optional<VkDeviceSize>(0));
    ASSERT_EQ(ranges.take(100, 256), std::optional<VkDeviceSize>(256));
    // The 246 bytes between them are still there for a small request.
    EXPECT_EQ(ranges.take(246, 1), std::optional<VkDeviceSize>(10));
    EXPECT_EQ(ranges.free_bytes(), 4096u - 10 - 100 - 246);
    ranges.give_back(256, 100);
    EXPECT_THROW(ranges.give_back(256, 100), std::logic_error) << "given back twice";
}

// A context of its own per test, so that no other test's blocks are counted or reused.
vk::Context fresh(std::uint64_t max_device_memory_bytes = 0) {
    return vk::Context::create(
        {.validation = true, .max_device_memory_bytes = max_device_memory_bytes});
}

VkMemoryRequirements requirements(const vk::Context& ctx, const vk::Buffer& b) {
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx.device(), b.get(), &req);
    return req;
}

// Many buffers alive at once (host-visible, to be written through their mappings on any
// device): each is filled with its own pattern and all are read back afterwards, so an overlap
// shows as a pattern overwritten; the ranges are also checked directly, with the alignment the
// driver asks of each buffer.
TEST(MemoryBlocks, BuffersShareFewBlocksWithoutOverlapAndAligned) {
    const vk::Context ctx = fresh();
    const auto before = ctx.memory_allocations();
    std::vector<vk::Buffer> buffers;
    std::mt19937 rng(11);
    for (int i = 0; i < 200; ++i) {
        const VkDeviceSize size = 4 + 4 * (rng() % 20000);
        buffers.emplace_back(ctx, size, vk::kStorageUsage, vk::MemoryUse::Readback,
                             "test.block." + std::to_string(i));
    }
    for (std::size_t i = 0; i < buffers.size(); ++i) {
        const vk::Buffer& b = buffers[i];
        ASSERT_TRUE(b.mapped());
        EXPECT_FALSE(b.memory().dedicated());
        EXPECT_EQ(b.memory().offset() % requirements(ctx, b).alignment, 0u);
        std::vector<std::uint32_t> pattern(b.size() / 4, std::uint32_t(i) * 2654435761u);
        std::memcpy(b.data(), pattern.data(), b.size());
    }
    for (std::size_t i = 0; i < buffers.size(); ++i) {
        const auto* words = static_cast<const std::uint32_t*>(buffers[i].data());
        const std::uint32_t want = std::uint32_t(i) * 2654435761u;
        for (VkDeviceSize w = 0; w < buffers[i].size() / 4; ++w)
            ASSERT_EQ(words[w], want) << "buffer " << i << " overwritten at word " << w;
        for (std::size_t j = 0; j < i; ++j) {
            const vk::MemoryAllocation& a = buffers[i].memory();
            const vk::MemoryAllocation& b = buffers[j].memory();
            if (a.memory() != b.memory()) continue;
            EXPECT_TRUE(a.offset() + a.size() <= b.offset() || b.offset() + b.size() <= a.offset())
                << "buffers " << i << " and " << j << " overlap";
        }
    }
    // 200 buffers of at most 80 KB (8 MB in all) fit one 64 MiB block.
    EXPECT_EQ(ctx.memory_allocations().total - before.total, 1u);
    buffers.clear();
    EXPECT_EQ(ctx.memory_allocations().live, before.live + 1) << "one empty block is kept";
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

TEST(MemoryBlocks, AFreedRangeIsReusedAndALargeRequestGetsItsOwnAllocation) {
    const vk::Context ctx = fresh();
    const auto before = ctx.memory_allocations();
    std::optional<vk::Buffer> first(std::in_place, ctx, 1 * kMiB, vk::kStorageUsage,
                                    vk::MemoryUse::Readback, "test.first");
    const vk::Buffer second(ctx, 1 * kMiB, vk::kStorageUsage, vk::MemoryUse::Readback,
                            "test.second");
    const VkDeviceMemory block = first->memory().memory();
    const VkDeviceSize offset = first->memory().offset();
    EXPECT_EQ(second.memory().memory(), block);
    first.reset();
    const vk::Buffer third(ctx, 512 * 1024, vk::kStorageUsage, vk::MemoryUse::Readback,
                           "test.third");
    EXPECT_EQ(third.memory().memory(), block);
    EXPECT_EQ(third.memory().offset(), offset) << "first fit: the freed range comes first";

    // Over half a block (64 MiB, or an eighth of a heap under 512 MiB): memory of its own.
    const auto live = ctx.memory_allocations().live;
    {
        const vk::Buffer large(ctx, 40 * kMiB, vk::kStorageUsage, vk::MemoryUse::Readback,
                               "test.large");
        EXPECT_TRUE(large.memory().dedicated());
        EXPECT_NE(large.memory().memory(), block);
        EXPECT_EQ(large.memory().offset(), 0u);
        EXPECT_EQ(ctx.memory_allocations().live, live + 1);
    }
    EXPECT_EQ(ctx.memory_allocations().live, live) << "a dedicated allocation goes back at once";
    EXPECT_EQ(ctx.memory_allocations().total - before.total, 2u); // the block and the large one
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

// The workbench's UI thread and its worker allocate side by side: two threads each make
// and drop buffers, writing their own pattern and checking it before the drop.
TEST(MemoryBlocks, TwoThreadsAllocatingAndFreeingNeverShareARange) {
    const vk::Context ctx = fresh();
    const auto before = ctx.memory_allocations();
    std::vector<std::string> failures(2);
    const auto work = [&](int thread) {
        std::mt19937 rng(100 + thread);
        std::vector<std::pair<vk::Buffer, std::uint32_t>> held;
        for (int step = 0; step < 1500 && failures[thread].empty(); ++step) {
            if (!held.empty() && (rng() % 2 == 0 || held.size() > 30)) {
                const std::size_t k = rng() % held.size();
                const auto& [b, want] = held[k];
                const auto* words = static_cast<const std::uint32_t*>(b.data());
                for (VkDeviceSize w = 0; w < b.size() / 4; ++w)
                    if (words[w] != want) {
                        failures[thread] = "a buffer overwritten by the other thread";
                        break;
                    }
                held.erase(held.begin() + std::ptrdiff_t(k));
            } else {
                const VkDeviceSize size = 4 + 4 * (rng() % 16000);
                vk::Buffer b(ctx, size, vk::kStorageUsage, vk::MemoryUse::Readback, "test.thread");
                const std::uint32_t want = (std::uint32_t(thread) << 24) | std::uint32_t(step);
                std::vector<std::uint32_t> pattern(size / 4, want);
                std::memcpy(b.data(), pattern.data(), size);
                held.emplace_back(std::move(b), want);
            }
        }
    };
    std::thread a(work, 0);
    std::thread b(work, 1);
    a.join();
    b.join();
    EXPECT_EQ(failures[0], "");
    EXPECT_EQ(failures[1], "");
    // At most 2 x 30 buffers of 64 KB (4 MB) live at once: one block serves both threads.
    EXPECT_EQ(ctx.memory_allocations().total - before.total, 1u);
    EXPECT_EQ(ctx.device_memory_in_use(), 0u) << "every charge given back";
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

// --max-device-memory charges what buffers ask for, not their blocks: a 4-byte buffer in
// a 64 MiB block fits a 1 MiB budget; past the budget, the error the command reports.
TEST(MemoryBlocks, TheBudgetChargesBuffersNotBlocksAndRefusesPastIt) {
    const vk::Context ctx = fresh(1 * kMiB);
    const vk::Buffer small(ctx, 4, vk::kStorageUsage, vk::MemoryUse::Readback, "test.small");
    std::optional<vk::Buffer> half(std::in_place, ctx, kMiB / 2, vk::kStorageUsage,
                                   vk::MemoryUse::Readback, "test.half");
    try {
        const vk::Buffer more(ctx, kMiB / 2, vk::kStorageUsage, vk::MemoryUse::Readback,
                              "test.over_budget");
        FAIL() << "a second half MiB beside the first and the small one is past 1 MiB";
    } catch (const vk::VulkanError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
        EXPECT_NE(what.find("out of device memory (the limit of 1 MB)"), std::string::npos) << what;
        EXPECT_NE(what.find("test.over_budget"), std::string::npos) << what;
        EXPECT_NE(what.find("--max-device-memory"), std::string::npos) << what;
    }
    half.reset(); // its charge given back: the same request fits now
    const vk::Buffer again(ctx, kMiB / 2, vk::kStorageUsage, vk::MemoryUse::Readback, "test.again");
    EXPECT_TRUE(again.mapped());
    EXPECT_EQ(ctx.validation_errors(), 0u);
}

} // namespace
} // namespace fird::test
