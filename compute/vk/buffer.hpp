// Buffers in ranges of the context's memory blocks; upload and readback through the shared
// queue.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "context.hpp"
#include "owned.hpp"

namespace fird::vk {

enum class MemoryUse {
    Device,   // device-local; filled by upload() through a staging buffer if not mappable
    Upload,   // host-visible, written by the CPU
    Readback, // host-visible (cached where possible), read by the CPU
};

class Buffer {
  public:
    Buffer() = default;
    // Sizes of 0 are rounded up to 4 bytes so empty inputs still bind a valid buffer.
    Buffer(const Context& ctx, VkDeviceSize size_bytes, VkBufferUsageFlags usage, MemoryUse use,
           std::string_view name);
    ~Buffer();
    Buffer(Buffer&&) noexcept;
    Buffer& operator=(Buffer&&) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    VkBuffer get() const { return buffer_.get(); }
    VkDeviceSize size() const { return size_; }
    bool mapped() const { return memory_.allocation.mapped() != nullptr; }
    void* data() const { return memory_.allocation.mapped(); }
    // Where its memory lies (tests check that no two live buffers overlap).
    const MemoryAllocation& memory() const { return memory_.allocation; }

    // Copies bytes in or out; uses a temporary staging buffer when not host-visible.
    void upload(const Context& ctx, std::span<const std::byte> bytes, VkDeviceSize offset = 0);
    void download(const Context& ctx, std::span<std::byte> bytes, VkDeviceSize offset = 0) const;

    template <typename T> void upload(const Context& ctx, std::span<const T> values) {
        upload(ctx, std::as_bytes(values));
    }
    template <typename T> std::vector<T> download_as(const Context& ctx, std::size_t count) const {
        std::vector<T> out(count);
        download(ctx, std::as_writable_bytes(std::span(out)));
        return out;
    }

  private:
    // The memory before the buffer: the buffer is destroyed first, so its range is never
    // handed to another buffer while this one still exists.
    Context::Memory memory_;
    Owned<VkBuffer> buffer_;
    VkDeviceSize size_ = 0;
};

// A typed view of a whole buffer for uniform or storage texel buffer bindings: on CPU
// drivers its reads are a vectorized gather instead of one bounds-checked scalar load per
// lane (the buffer needs VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT or
// VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT, as it is bound).
class TexelView {
  public:
    TexelView() = default;
    TexelView(const Context& ctx, const Buffer& buffer, VkFormat format, std::string_view name);
    VkBufferView get() const { return view_.get(); }

  private:
    Owned<VkBufferView> view_;
};

// A view of a whole buffer holds at most maxTexelBufferElements texels (Vulkan allows a
// device as few as 65536): throws std::invalid_argument, one line naming `what` and the
// limit, where `texels` would pass it. TexelView checks its own; owners check before they
// allocate, naming what the user asked for.
void require_texel_count(const Context& ctx, std::uint64_t texels, std::string_view what);

// Buffer usage for storage buffers that are also copied to and from.
inline constexpr VkBufferUsageFlags kStorageUsage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                    VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                                    VK_BUFFER_USAGE_TRANSFER_DST_BIT;

// A full memory barrier between compute/transfer/graphics work on the one queue.
void barrier_all(VkCommandBuffer cb);
// Makes the device's writes so far visible to the host's reads of mapped memory after the
// submission's fence (the last command of a recording whose results the host reads).
void barrier_to_host(VkCommandBuffer cb);

} // namespace fird::vk
