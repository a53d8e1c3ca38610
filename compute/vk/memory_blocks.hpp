// Device memory suballocated from a few large blocks (issue 24): FIRD's own small block
// allocator, since Debian 12 ships no Vulkan Memory Allocator. A driver may allow as few
// as 4096 vkAllocateMemory objects, and each one costs a kernel call (and on a discrete
// GPU a page-table update); a trace used to make one per buffer, dozens per evaluation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

namespace fird::vk {

// The free ranges of one block: first fit; a range given back is joined to free
// neighbours, so a block whose ranges all came back is one free range again.
class BlockRanges {
  public:
    explicit BlockRanges(VkDeviceSize size_bytes);
    // The offset of a range of size_bytes aligned to alignment (a power of two), or none
    // when no free range holds it. The padding before the offset stays free.
    std::optional<VkDeviceSize> take(VkDeviceSize size_bytes, VkDeviceSize alignment);
    // Returns a range that take() handed out.
    void give_back(VkDeviceSize offset, VkDeviceSize size_bytes);
    bool unused() const;             // the whole block is one free range
    std::size_t free_ranges() const; // separate free ranges (1 when unused)
    VkDeviceSize free_bytes() const;

  private:
    VkDeviceSize size_;
    std::map<VkDeviceSize, VkDeviceSize> free_; // offset -> size, never adjacent
};

// How many vkAllocateMemory objects exist now and were made since the context's creation.
struct MemoryAllocationCounts {
    std::uint64_t live = 0;
    std::uint64_t total = 0;
};

class MemoryBlocks;
struct MemoryBlock;

// One buffer's or image's memory: a range of a block, or an allocation of its own; the
// range goes back to its block when this dies. Move-only.
class MemoryAllocation {
  public:
    MemoryAllocation() = default;
    ~MemoryAllocation();
    MemoryAllocation(MemoryAllocation&& o) noexcept;
    MemoryAllocation& operator=(MemoryAllocation&& o) noexcept;
    MemoryAllocation(const MemoryAllocation&) = delete;
    MemoryAllocation& operator=(const MemoryAllocation&) = delete;

    VkDeviceMemory memory() const;
    VkDeviceSize offset() const { return offset_; }
    VkDeviceSize size() const { return size_; }
    // The block's mapping plus the offset: null unless the memory is host-visible and
    // coherent (FIRD never maps non-coherent memory, so no range needs flushing and
    // nonCoherentAtomSize never applies).
    void* mapped() const;
    bool dedicated() const;

  private:
    friend class MemoryBlocks;
    void release();
    MemoryBlocks* owner_ = nullptr;
    MemoryBlock* block_ = nullptr;
    VkDeviceSize offset_ = 0;
    VkDeviceSize size_ = 0;
};

struct MemoryBlocksOptions {
    // The size of a shared block; a memory type on a smaller heap gets an eighth of it.
    VkDeviceSize block_bytes = VkDeviceSize(64) << 20;
    // Ask the kernel for transparent huge pages on each mapped block (CPU drivers).
    bool advise_huge_pages = false;
    // Gives each new VkDeviceMemory a debug name (a block's, or the dedicated buffer's).
    std::function<void(VkDeviceMemory, std::string_view)> name_memory;
};

// The blocks of every memory type of one device. Thread-safe: the workbench's UI thread
// and its worker allocate and free side by side. Blocks and handles must not outlive it.
class MemoryBlocks {
  public:
    MemoryBlocks(VkDevice device, const VkPhysicalDeviceMemoryProperties& properties,
                 VkDeviceSize max_allocation_bytes, const MemoryBlocksOptions& options);
    ~MemoryBlocks();
    MemoryBlocks(const MemoryBlocks&) = delete;
    MemoryBlocks& operator=(const MemoryBlocks&) = delete;

    // A range for req in memory type `type`, from a shared block when it is at most half
    // a block and not `dedicated`; otherwise an allocation of its own (named `name`).
    // A failed vkAllocateMemory throws VulkanError with the driver's result.
    MemoryAllocation allocate(const VkMemoryRequirements& req, std::uint32_t type, bool dedicated,
                              std::string_view name);
    MemoryAllocationCounts counts() const;
    // The shared block size of a memory type.
    VkDeviceSize block_bytes(std::uint32_t type) const;

  private:
    friend class MemoryAllocation;
    void release(MemoryBlock* block, VkDeviceSize offset, VkDeviceSize size);
    MemoryBlock& new_block(std::uint32_t type, VkDeviceSize size, bool dedicated);

    VkDevice device_;
    VkPhysicalDeviceMemoryProperties properties_;
    VkDeviceSize max_allocation_bytes_;
    MemoryBlocksOptions options_;
    mutable std::mutex mutex_;
    std::vector<std::unique_ptr<MemoryBlock>> blocks_;
    MemoryAllocationCounts counts_;
};

} // namespace fird::vk
