#include "buffer.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "check.hpp"

namespace fird::vk {

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
    memory_ = ctx.allocate_memory(req, type, name);
    FIRD_VK_CHECK(
        vkBindBufferMemory(dev, buffer, memory_.allocation.memory(), memory_.allocation.offset()));
}

Buffer::~Buffer() = default;
Buffer::Buffer(Buffer&&) noexcept = default;
Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) { // the old buffer goes before its memory, as in the destructor
        buffer_ = std::move(o.buffer_);
        memory_ = std::move(o.memory_);
        size_ = o.size_;
    }
    return *this;
}

void Buffer::upload(const Context& ctx, std::span<const std::byte> bytes, VkDeviceSize offset) {
    if (bytes.empty()) return;
    if (offset + bytes.size() > size_) throw std::out_of_range("Buffer::upload past the end");
    if (mapped()) {
        std::memcpy(static_cast<std::byte*>(data()) + offset, bytes.data(), bytes.size());
        return;
    }
    Buffer staging(ctx, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload,
                   "fird.staging.upload");
    std::memcpy(staging.data(), bytes.data(), bytes.size());
    ctx.count_staging_copy();
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        const VkBufferCopy region{.srcOffset = 0, .dstOffset = offset, .size = bytes.size()};
        vkCmdCopyBuffer(cb, staging.get(), get(), 1, &region);
    });
}

void Buffer::download(const Context& ctx, std::span<std::byte> bytes, VkDeviceSize offset) const {
    if (bytes.empty()) return;
    if (offset + bytes.size() > size_) throw std::out_of_range("Buffer::download past the end");
    if (mapped()) {
        std::memcpy(bytes.data(), static_cast<const std::byte*>(data()) + offset, bytes.size());
        return;
    }
    Buffer staging(ctx, bytes.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::Readback,
                   "fird.staging.readback");
    ctx.count_staging_copy();
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

namespace {
// The bytes of one texel of the formats FIRD's views use.
VkDeviceSize texel_bytes(VkFormat format) {
    switch (format) {
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
        return 4;
    case VK_FORMAT_R32G32_SFLOAT:
        return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
        return 16;
    default:
        throw std::logic_error(fmt::format("TexelView: format {} has no size here", int(format)));
    }
}
} // namespace

void require_texel_count(const Context& ctx, std::uint64_t texels, std::string_view what) {
    const std::uint64_t limit = ctx.limits().max_texel_buffer_elements;
    if (texels > limit)
        throw std::invalid_argument(fmt::format(
            "{} needs {} texels, past this device's texel buffer limit ({})", what, texels, limit));
}

TexelView::TexelView(const Context& ctx, const Buffer& buffer, VkFormat format,
                     std::string_view name) {
    require_texel_count(ctx, buffer.size() / texel_bytes(format), name);
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
