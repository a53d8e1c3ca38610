#include "submission.hpp"

#include <utility>

#include "buffer.hpp"
#include "check.hpp"
#include "context.hpp"

namespace fird::vk {

namespace {
// As Context::submit_and_wait's: a submission that runs this long has hung the device.
constexpr std::uint64_t kTimeoutNs = 600ull * 1000 * 1000 * 1000;
} // namespace

Submission::Submission(const Context& ctx, const std::function<void(VkCommandBuffer)>& record,
                       const char* name)
    : ctx_(&ctx) {
    const VkDevice device = ctx.device();
    const VkCommandPoolCreateInfo pool_info{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                            .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
                                            .queueFamilyIndex = ctx.queue_family()};
    VkCommandPool pool = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateCommandPool(device, &pool_info, nullptr, &pool));
    pool_ = Owned<VkCommandPool>(device, pool);
    ctx.name(pool, VK_OBJECT_TYPE_COMMAND_POOL, name);
    const VkCommandBufferAllocateInfo alloc{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                            .commandPool = pool,
                                            .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                            .commandBufferCount = 1};
    VkCommandBuffer cb = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &cb));
    ctx.name(cb, VK_OBJECT_TYPE_COMMAND_BUFFER, name);
    const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                         .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FIRD_VK_CHECK(vkBeginCommandBuffer(cb, &begin));
    // Writes from the other queue (the worker's, when it has its own) were ordered before
    // this by a fence the host waited on, which makes them available, not visible: this
    // barrier makes them visible to what follows.
    barrier_all(cb);
    record(cb);
    FIRD_VK_CHECK(vkEndCommandBuffer(cb));
    const VkFenceCreateInfo fence_info{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &fence));
    Owned<VkFence> owned_fence(device, fence);
    ctx.name(fence, VK_OBJECT_TYPE_FENCE, name);
    const VkSubmitInfo submit{
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO, .commandBufferCount = 1, .pCommandBuffers = &cb};
    {
        const auto queue = ctx.lock_queue();
        FIRD_VK_CHECK(vkQueueSubmit(ctx.queue(), 1, &submit, fence));
    }
    fence_ = std::move(owned_fence); // submitted: from here on it is waited for
}

Submission::~Submission() {
    // A destructor must not throw: a device lost here was (or will be) reported by the
    // next submission's wait.
    if (!submitted()) return;
    const VkFence fence = fence_.get();
    (void)vkWaitForFences(ctx_->device(), 1, &fence, VK_TRUE, kTimeoutNs);
}

Submission& Submission::operator=(Submission&& o) noexcept {
    if (this != &o) {
        if (submitted()) {
            const VkFence fence = fence_.get();
            (void)vkWaitForFences(ctx_->device(), 1, &fence, VK_TRUE, kTimeoutNs);
        }
        ctx_ = o.ctx_;
        pool_ = std::move(o.pool_);
        fence_ = std::move(o.fence_);
    }
    return *this;
}

bool Submission::done() const {
    if (!submitted()) return true;
    const VkResult r = vkGetFenceStatus(ctx_->device(), fence_.get());
    if (r == VK_NOT_READY) return false;
    FIRD_VK_CHECK(r);
    return true;
}

void Submission::wait() const {
    if (!submitted()) return;
    const VkFence fence = fence_.get();
    const VkResult r = vkWaitForFences(ctx_->device(), 1, &fence, VK_TRUE, kTimeoutNs);
    if (r == VK_TIMEOUT)
        throw VulkanError("vkWaitForFences: the device did not finish within 600 s", VK_TIMEOUT);
    FIRD_VK_CHECK(r);
}

} // namespace fird::vk
