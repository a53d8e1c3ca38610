#include "timer.hpp"

#include "check.hpp"

namespace fird::vk {

GpuTimer::GpuTimer(const Context& ctx) : ctx_(&ctx) {
    if (!ctx.limits().timestamps) return;
    const VkQueryPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                     .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                     .queryCount = 2};
    VkQueryPool pool = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateQueryPool(ctx.device(), &info, nullptr, &pool));
    pool_ = Owned<VkQueryPool>(ctx.device(), pool);
    ctx.name(pool, VK_OBJECT_TYPE_QUERY_POOL, "fird.timer");
}

void GpuTimer::begin(VkCommandBuffer cb) const {
    if (!pool_) return;
    vkCmdResetQueryPool(cb, pool_.get(), 0, 2);
    vkCmdWriteTimestamp2(cb, VK_PIPELINE_STAGE_2_NONE, pool_.get(), 0);
}

void GpuTimer::end(VkCommandBuffer cb) const {
    if (!pool_) return;
    vkCmdWriteTimestamp2(cb, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_.get(), 1);
}

double GpuTimer::elapsed_ms() const {
    if (!pool_) return 0.0;
    std::uint64_t t[2] = {};
    FIRD_VK_CHECK(vkGetQueryPoolResults(ctx_->device(), pool_.get(), 0, 2, sizeof(t), t,
                                        sizeof(std::uint64_t),
                                        VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    return double(t[1] - t[0]) * ctx_->limits().timestamp_period_ns * 1e-6;
}

} // namespace fird::vk
