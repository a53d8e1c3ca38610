#include "memory_blocks.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <sys/mman.h>

#include "check.hpp"

namespace fird::vk {

struct MemoryBlock {
    VkDeviceMemory memory = VK_NULL_HANDLE;
    std::uint32_t type = 0;
    bool dedicated = false;
    std::byte* mapped = nullptr;
    BlockRanges ranges;
};

namespace {

// No two buffers share a cache line: on a CPU driver a buffer's atomics (the counters)
// would otherwise bounce the line its neighbour's writers use. Drivers ask for at least
// this much on most buffers anyway.
constexpr VkDeviceSize kMinAlignment = 64;

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize alignment) {
    return (v + alignment - 1) & ~(alignment - 1);
}

// On a CPU driver (lavapipe) device memory is the process's own anonymous memory, and a
// large buffer's first touch costs one page fault per 4 KiB page: 0.4-0.5 s of a
// 1e7-ray evaluation went to faulting in the rayset and the ping-pong buffers. Asking
// the kernel for transparent huge pages (one fault per 2 MiB) where it honours the
// advice (the "madvise" setting, Debian's default) removes nearly all of it. Only the
// 2 MiB-aligned interior of the mapping is advised; a refused advice changes nothing.
void advise_huge_pages(void* mapped, VkDeviceSize size) {
    constexpr std::uintptr_t kHuge = std::uintptr_t(2) << 20;
    const auto begin = reinterpret_cast<std::uintptr_t>(mapped);
    const std::uintptr_t first = (begin + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t last = (begin + size) & ~(kHuge - 1);
    if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
}

} // namespace

BlockRanges::BlockRanges(VkDeviceSize size_bytes) : size_(size_bytes) {
    if (size_bytes > 0) free_.emplace(0, size_bytes);
}

std::optional<VkDeviceSize> BlockRanges::take(VkDeviceSize size_bytes, VkDeviceSize alignment) {
    if (size_bytes == 0 || alignment == 0 || (alignment & (alignment - 1)) != 0)
        throw std::invalid_argument("BlockRanges::take: an empty range or an alignment that is "
                                    "not a power of two");
    for (auto it = free_.begin(); it != free_.end(); ++it) {
        const VkDeviceSize begin = it->first;
        const VkDeviceSize end = begin + it->second;
        const VkDeviceSize at = align_up(begin, alignment);
        if (at > end || end - at < size_bytes) continue;
        free_.erase(it);
        if (at > begin) free_.emplace(begin, at - begin);
        if (at + size_bytes < end) free_.emplace(at + size_bytes, end - at - size_bytes);
        return at;
    }
    return std::nullopt;
}

void BlockRanges::give_back(VkDeviceSize offset, VkDeviceSize size_bytes) {
    if (size_bytes == 0 || offset > size_ || size_ - offset < size_bytes)
        throw std::logic_error("BlockRanges::give_back: a range outside the block");
    VkDeviceSize begin = offset;
    VkDeviceSize end = offset + size_bytes;
    auto next = free_.lower_bound(offset);
    if (next != free_.end() && next->first < end)
        throw std::logic_error("BlockRanges::give_back: the range is already free");
    if (next != free_.begin()) {
        const auto prev = std::prev(next);
        const VkDeviceSize prev_end = prev->first + prev->second;
        if (prev_end > offset)
            throw std::logic_error("BlockRanges::give_back: the range is already free");
        if (prev_end == offset) {
            begin = prev->first;
            free_.erase(prev);
        }
    }
    if (next != free_.end() && next->first == end) {
        end += next->second;
        free_.erase(next);
    }
    free_.emplace(begin, end - begin);
}

bool BlockRanges::unused() const {
    return free_.size() == 1 && free_.begin()->second == size_;
}

std::size_t BlockRanges::free_ranges() const {
    return free_.size();
}

VkDeviceSize BlockRanges::free_bytes() const {
    VkDeviceSize sum = 0;
    for (const auto& [offset, size] : free_)
        sum += size;
    return sum;
}

MemoryAllocation::~MemoryAllocation() {
    release();
}

MemoryAllocation::MemoryAllocation(MemoryAllocation&& o) noexcept
    : owner_(std::exchange(o.owner_, nullptr)), block_(std::exchange(o.block_, nullptr)),
      offset_(o.offset_), size_(o.size_) {}

MemoryAllocation& MemoryAllocation::operator=(MemoryAllocation&& o) noexcept {
    if (this != &o) {
        release();
        owner_ = std::exchange(o.owner_, nullptr);
        block_ = std::exchange(o.block_, nullptr);
        offset_ = o.offset_;
        size_ = o.size_;
    }
    return *this;
}

void MemoryAllocation::release() {
    if (owner_) owner_->release(block_, offset_, size_);
    owner_ = nullptr;
    block_ = nullptr;
}

VkDeviceMemory MemoryAllocation::memory() const {
    return block_ ? block_->memory : VK_NULL_HANDLE;
}

void* MemoryAllocation::mapped() const {
    return block_ && block_->mapped ? block_->mapped + offset_ : nullptr;
}

bool MemoryAllocation::dedicated() const {
    return block_ && block_->dedicated;
}

MemoryBlocks::MemoryBlocks(VkDevice device, const VkPhysicalDeviceMemoryProperties& properties,
                           VkDeviceSize max_allocation_bytes, const MemoryBlocksOptions& options)
    : device_(device), properties_(properties), max_allocation_bytes_(max_allocation_bytes),
      options_(options) {}

MemoryBlocks::~MemoryBlocks() {
    for (const auto& b : blocks_)
        vkFreeMemory(device_, b->memory, nullptr); // unmaps implicitly
}

VkDeviceSize MemoryBlocks::block_bytes(std::uint32_t type) const {
    const VkDeviceSize heap = properties_.memoryHeaps[properties_.memoryTypes[type].heapIndex].size;
    VkDeviceSize bytes = std::min(options_.block_bytes, heap / 8);
    if (max_allocation_bytes_ > 0) bytes = std::min(bytes, max_allocation_bytes_);
    return std::max<VkDeviceSize>(bytes, kMinAlignment);
}

MemoryAllocationCounts MemoryBlocks::counts() const {
    const std::lock_guard lock(mutex_);
    return counts_;
}

MemoryBlock& MemoryBlocks::new_block(std::uint32_t type, VkDeviceSize size, bool dedicated) {
    const VkMemoryAllocateInfo info{.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                    .allocationSize = size,
                                    .memoryTypeIndex = type};
    VkDeviceMemory memory = VK_NULL_HANDLE;
    const VkResult r = vkAllocateMemory(device_, &info, nullptr, &memory);
    if (r != VK_SUCCESS)
        throw VulkanError(fmt::format("vkAllocateMemory of {} bytes: {}", size, result_name(r)), r);
    auto block = std::make_unique<MemoryBlock>(MemoryBlock{
        .memory = memory, .type = type, .dedicated = dedicated, .ranges = BlockRanges(size)});
    const auto host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if ((properties_.memoryTypes[type].propertyFlags & host) == host) {
        void* mapped = nullptr;
        const VkResult m = vkMapMemory(device_, memory, 0, VK_WHOLE_SIZE, 0, &mapped);
        if (m != VK_SUCCESS) {
            vkFreeMemory(device_, memory, nullptr);
            throw VulkanError(fmt::format("vkMapMemory: {}", result_name(m)), m);
        }
        block->mapped = static_cast<std::byte*>(mapped);
        if (options_.advise_huge_pages) advise_huge_pages(mapped, size);
    }
    ++counts_.live;
    ++counts_.total;
    blocks_.push_back(std::move(block));
    return *blocks_.back();
}

MemoryAllocation MemoryBlocks::allocate(const VkMemoryRequirements& req, std::uint32_t type,
                                        bool dedicated, std::string_view name) {
    if (type >= properties_.memoryTypeCount || req.size == 0)
        throw std::invalid_argument("MemoryBlocks::allocate: no such memory type, or 0 bytes");
    const VkDeviceSize block = block_bytes(type);
    const VkDeviceSize alignment = std::max(req.alignment, kMinAlignment);
    const std::lock_guard lock(mutex_);
    MemoryAllocation a;
    const auto place = [&](MemoryBlock& b, VkDeviceSize offset, VkDeviceSize size) {
        a.owner_ = this;
        a.block_ = &b;
        a.offset_ = offset;
        a.size_ = size;
    };
    // An allocation of its own: the block is exactly the request, used whole.
    const auto own = [&] {
        MemoryBlock& b = new_block(type, req.size, true);
        (void)b.ranges.take(req.size, 1);
        if (options_.name_memory) options_.name_memory(b.memory, name);
        place(b, 0, req.size);
    };
    if (dedicated || req.size > block / 2) {
        own();
        return a;
    }
    for (const auto& b : blocks_)
        if (!b->dedicated && b->type == type)
            if (const auto offset = b->ranges.take(req.size, alignment)) {
                place(*b, *offset, req.size);
                return a;
            }
    try {
        MemoryBlock& b = new_block(type, block, false);
        if (options_.name_memory)
            options_.name_memory(b.memory, fmt::format("fird.memory.block.type{}", type));
        place(b, *b.ranges.take(req.size, alignment), req.size);
    } catch (const VulkanError& e) {
        // A whole block may not fit where the request alone still does.
        if (e.result() != VK_ERROR_OUT_OF_DEVICE_MEMORY &&
            e.result() != VK_ERROR_OUT_OF_HOST_MEMORY)
            throw;
        own();
    }
    return a;
}

void MemoryBlocks::release(MemoryBlock* block, VkDeviceSize offset, VkDeviceSize size) {
    const std::lock_guard lock(mutex_);
    block->ranges.give_back(offset, size);
    if (!block->ranges.unused()) return;
    // A shared block left empty is kept while no other empty one of its type is: a pass
    // that makes and drops its scratch on every call (the reduction, trace_paths) would
    // otherwise allocate and free a block each time. A dedicated one goes back at once.
    if (!block->dedicated && std::none_of(blocks_.begin(), blocks_.end(), [&](const auto& b) {
            return b.get() != block && !b->dedicated && b->type == block->type &&
                   b->ranges.unused();
        }))
        return;
    vkFreeMemory(device_, block->memory, nullptr);
    blocks_.erase(std::find_if(blocks_.begin(), blocks_.end(),
                               [&](const auto& b) { return b.get() == block; }));
    --counts_.live;
}

} // namespace fird::vk
