// The one Vulkan instance and logical device that compute, render and ui share.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <vulkan/vulkan.h>

#include "memory_blocks.hpp"
#include "owned.hpp"

namespace fird::vk {

struct ContextOptions {
    // Enable VK_LAYER_KHRONOS_validation if installed; every validation error is
    // counted (validation_errors()) so tests can fail on them.
    bool validation = false;
    // Choose the device whose name contains this text (case-insensitive); empty: best.
    std::string device_name;
    // Without a device_name: a rank of an MPI job opens the device of its rank on the node
    // (this modulo the count of usable devices of the best kind; ranks beyond share them).
    std::optional<std::uint32_t> local_rank;
    // Extra instance extensions (a window system's surface extensions, from ui).
    std::vector<std::string> instance_extensions;
    // Extra device extensions (VK_KHR_swapchain, from ui).
    std::vector<std::string> device_extensions;
    // Refuse device allocations past this many bytes in all (0: as the device allows): the
    // --max-device-memory option, which also lets tests provoke out-of-memory on lavapipe.
    std::uint64_t max_device_memory_bytes = 0;
    // Trace at most this many rays per submission (0: as the device allows). A device
    // shared with a window keeps its submissions short, so a frame queued behind the
    // compute work waits for one small batch, not a whole evaluation (lavapipe runs a
    // queue's submissions one after another).
    std::uint64_t max_batch_rays = 0;
    // Submit long work in pieces (yield_queue between passes: an evaluation's bounces), so
    // that a window's frame waits behind one pass, not a whole batch; results are the same.
    bool yield_between_passes = false;
};

class Context;

// Locks on every queue (the frames' and the work's, when apart): what vkDeviceWaitIdle or
// a swapchain's re-creation needs, since they use every queue.
struct QueueLocks {
    std::unique_lock<std::mutex> frames, work;
};

// The bytes one allocation holds against the context's budget, given back when it dies.
class MemoryCharge {
  public:
    MemoryCharge() = default;
    MemoryCharge(const Context* ctx, std::uint64_t bytes) : ctx_(ctx), bytes_(bytes) {}
    ~MemoryCharge();
    MemoryCharge(MemoryCharge&& o) noexcept
        : ctx_(std::exchange(o.ctx_, nullptr)), bytes_(std::exchange(o.bytes_, 0)) {}
    MemoryCharge& operator=(MemoryCharge&& o) noexcept;
    MemoryCharge(const MemoryCharge&) = delete;
    MemoryCharge& operator=(const MemoryCharge&) = delete;

  private:
    const Context* ctx_ = nullptr;
    std::uint64_t bytes_ = 0;
};

// What `fird info` reports, and what passes consult to size their work.
struct DeviceSummary {
    std::string name;
    std::string type; // "discrete", "integrated", "virtual", "cpu", "other"
    std::string driver_name;
    std::string driver_info;
    std::uint32_t driver_version = 0; // driverVersion, in the vendor's own encoding
    std::uint32_t api_version = 0;
    bool usable = false; // Vulkan 1.3 with a graphics+compute queue and the extensions we need
    std::string unusable_reason;
};

struct DeviceLimits {
    std::uint32_t max_workgroup_size[3] = {};
    std::uint32_t max_workgroup_invocations = 0;
    std::uint32_t max_workgroup_count[3] = {};
    std::uint64_t max_storage_buffer_range = 0;
    std::uint64_t max_texel_buffer_elements = 0;
    std::uint64_t max_memory_allocation_size = 0;
    std::uint64_t device_local_heap_bytes = 0;
    std::uint32_t subgroup_size = 0;
    bool float32_atomic_add = false; // VK_EXT_shader_atomic_float, buffer float add
    bool timestamps = false;         // timestampComputeAndGraphics on our queue
    float timestamp_period_ns = 0.0f;
    std::uint32_t max_image_dimension_2d = 0;
};

class Context {
  public:
    static Context create(const ContextOptions& options);
    ~Context();
    Context(Context&&) noexcept;
    Context& operator=(Context&&) noexcept;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const;
    VkPhysicalDevice physical_device() const;
    VkDevice device() const;
    VkQueue queue() const;
    std::uint32_t queue_family() const;
    const DeviceSummary& summary() const;
    const DeviceLimits& limits() const;
    // Every device found, in enumeration order, and which one was chosen.
    const std::vector<DeviceSummary>& all_devices() const;
    bool validation_enabled() const;
    std::uint64_t max_batch_rays() const; // ContextOptions::max_batch_rays
    // Validation-layer errors reported since creation.
    std::uint64_t validation_errors() const;
    // Command buffers submitted through submit_and_wait since creation (each one a host
    // wait): what an evaluation costs in round trips (fird trace --json --profile).
    std::uint64_t submissions() const;
    // Of those, the copies through a staging buffer (vk::Buffer's upload and download
    // where its memory is not host-visible, as on a discrete GPU; none on lavapipe), kept
    // apart so that a count of the work's submissions reads the same on every device.
    std::uint64_t staging_copies() const;
    void count_staging_copy() const; // by vk::Buffer, before each such submission
    // vkAllocateMemory objects alive now and made since creation (every buffer's and
    // image's memory comes from one): fird trace --json --profile reports the evaluation's.
    MemoryAllocationCounts memory_allocations() const;

    // Attach a debug name, so validation messages say which buffer or pipeline.
    void set_name(VkObjectType type, std::uint64_t handle, std::string_view name) const;
    template <typename Handle>
    void name(Handle handle, VkObjectType type, std::string_view text) const {
        set_name(type, reinterpret_cast<std::uint64_t>(handle), text);
    }

    // Records commands into a one-time command buffer (from this thread's own pool),
    // submits it on the work queue (queue() unless separate_work_queue()) and waits on a fence.
    // Safe from several threads. Throws VulkanError on device loss.
    void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;
    // Inside submit_and_wait's `record`: with ContextOptions::yield_between_passes, submits
    // what `cb` holds so far, waits, and lets the recording go on in the same buffer (the
    // queue is free for others in between). Otherwise nothing.
    void yield_queue(VkCommandBuffer cb) const;

    // Held around every submission and present on queue() (Vulkan requires external
    // synchronization of a queue): take it for your own vkQueueSubmit there.
    std::unique_lock<std::mutex> lock_queue() const;
    QueueLocks lock_all_queues() const;
    // Whether submit_and_wait's work runs on a queue of its own (a second queue of the
    // universal family, where the device has one), apart from queue()'s frames.
    bool separate_work_queue() const;

    // Memory for one buffer or image within the budget, suballocated from a shared block
    // (memory_blocks.hpp) unless `dedicated`. The budget is charged the request's own
    // size, not its block's slack: --max-device-memory bounds what FIRD's work needs, the
    // same figure whatever the block size (a limit below one block would otherwise fail
    // every trace); the slack is bounded by one empty block kept per memory type plus
    // the holes between ranges. Out of memory (the budget's or the device's) is a
    // VulkanError that names the allocation and says what to lower.
    struct Memory {
        MemoryAllocation allocation;
        MemoryCharge charge;
    };
    Memory allocate_memory(const VkMemoryRequirements& req, std::uint32_t type,
                           std::string_view name, bool dedicated = false) const;
    std::uint64_t device_memory_in_use() const;
    // The --max-device-memory budget (ContextOptions::max_device_memory_bytes; 0: none).
    std::uint64_t device_memory_budget() const;

    std::uint32_t find_memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                   VkMemoryPropertyFlags preferred) const;

  private:
    friend class MemoryCharge;
    void release_memory(std::uint64_t bytes) const;
    struct State;
    explicit Context(std::unique_ptr<State> state);
    std::unique_ptr<State> state_;
};

// Lists devices without creating a logical device (for `fird info` and errors).
std::vector<DeviceSummary> enumerate_devices();

} // namespace fird::vk
