#include "buffer.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <sys/mman.h>

#include "check.hpp"

namespace fird::vk {
namespace {

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

Buffer::Buffer(const Context& ctx, VkDeviceSize size_bytes, VkBufferUsageFlags usage, MemoryUse use,
               std::string_view name)
    : size_(size_bytes == 0 ? 4 : size_bytes) {
    const VkDevice dev = ctx.device();
    const VkBufferCreateInfo info{.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                                  .size = size_,
                                  .usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                           VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  .sharingMode = VK_SHARING_MODE_EXCLUSIVE};
    VkBuffer buffer = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateBuffer(dev, &info, nullptr, &buffer));
    buffer_ = Owned<VkBuffer>(dev, buffer);
    ctx.name(buffer, VK_OBJECT_TYPE_BUFFER, name);

    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(dev, buffer, &req);
    VkMemoryPropertyFlags required = 0;
    VkMemoryPropertyFlags preferred = 0;
    switch (use) {
    case MemoryUse::Device:
        preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
    case MemoryUse::Upload:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        break;
    case MemoryUse::Readback:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    const std::uint32_t type = ctx.find_memory_type(req.memoryTypeBits, required, preferred);
    const VkMemoryAllocateInfo alloc{.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                     .allocationSize = req.size,
                                     .memoryTypeIndex = type};
    VkDeviceMemory memory = VK_NULL_HANDLE;
    charge_ = ctx.allocate_memory(alloc, name, &memory);
    memory_ = Owned<VkDeviceMemory>(dev, memory);
    ctx.name(memory, VK_OBJECT_TYPE_DEVICE_MEMORY, name);
    FIRD_VK_CHECK(vkBindBufferMemory(dev, buffer, memory, 0));

    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(ctx.physical_device(), &props);
    const auto flags = props.memoryTypes[type].propertyFlags;
    const auto host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if ((flags & host) == host) {
        FIRD_VK_CHECK(vkMapMemory(dev, memory, 0, VK_WHOLE_SIZE, 0, &mapped_));
        if (ctx.summary().type == "cpu") advise_huge_pages(mapped_, req.size);
    }
}

Buffer::~Buffer() = default; // memory is unmapped implicitly by vkFreeMemory
Buffer::Buffer(Buffer&& o) noexcept
    : buffer_(std::move(o.buffer_)), memory_(std::move(o.memory_)), charge_(std::move(o.charge_)),
      size_(o.size_), mapped_(std::exchange(o.mapped_, nullptr)) {}
Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        buffer_ = std::move(o.buffer_);
        memory_ = std::move(o.memory_);
        charge_ = std::move(o.charge_);
        size_ = o.size_;
        mapped_ = std::exchange(o.mapped_, nullptr);
    }
    return *this;
}

void Buffer::upload(const Context& ctx, std::span<const std::byte> bytes, VkDeviceSize offset) {
    if (bytes.empty()) return;
    if (offset + bytes.size() > size_) throw std::out_of_range("Buffer::upload past the end");
    if (mapped_) {
        std::memcpy(static_cast<std::byte*>(mapped_) + offset, bytes.data(), bytes.size());
        return;
    }
    Buffer staging(ctx, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload,
                   "fird.staging.upload");
    std::memcpy(staging.data(), bytes.data(), bytes.size());
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        const VkBufferCopy region{.srcOffset = 0, .dstOffset = offset, .size = bytes.size()};
        vkCmdCopyBuffer(cb, staging.get(), get(), 1, &region);
    });
}

void Buffer::download(const Context& ctx, std::span<std::byte> bytes, VkDeviceSize offset) const {
    if (bytes.empty()) return;
    if (offset + bytes.size() > size_) throw std::out_of_range("Buffer::download past the end");
    if (mapped_) {
        std::memcpy(bytes.data(), static_cast<const std::byte*>(mapped_) + offset, bytes.size());
        return;
    }
    Buffer staging(ctx, bytes.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback,
                   "fird.staging.readback");
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        const VkBufferCopy region{.srcOffset = offset, .dstOffset = 0, .size = bytes.size()};
        vkCmdCopyBuffer(cb, get(), staging.get(), 1, &region);
    });
    std::memcpy(bytes.data(), staging.data(), bytes.size());
}

namespace {
// Every write so far (any stage) before the given stages' accesses.
void writes_before(VkCommandBuffer cb, VkPipelineStageFlags2 stages, VkAccessFlags2 access) {
    const VkMemoryBarrier2 mb{.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                              .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                              .srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT,
                              .dstStageMask = stages,
                              .dstAccessMask = access};
    const VkDependencyInfo dep{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                               .memoryBarrierCount = 1,
                               .pMemoryBarriers = &mb};
    vkCmdPipelineBarrier2(cb, &dep);
}
} // namespace

void barrier_all(VkCommandBuffer cb) {
    writes_before(cb, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                  VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
}

void barrier_to_host(VkCommandBuffer cb) {
    writes_before(cb, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

} // namespace fird::vk

namespace fird::vk {

TexelView::TexelView(const Context& ctx, const Buffer& buffer, VkFormat format,
                     std::string_view name) {
    const VkBufferViewCreateInfo info{.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO,
                                      .buffer = buffer.get(),
                                      .format = format,
                                      .offset = 0,
                                      .range = VK_WHOLE_SIZE};
    VkBufferView view = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateBufferView(ctx.device(), &info, nullptr, &view));
    view_ = Owned<VkBufferView>(ctx.device(), view);
    ctx.name(view, VK_OBJECT_TYPE_BUFFER_VIEW, name);
}

} // namespace fird::vk
