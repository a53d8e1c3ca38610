#include "timer.hpp"

#include <stdexcept>

#include "check.hpp"

namespace fird::vk {

GpuTimer::GpuTimer(const Context& ctx, std::uint32_t pairs) : ctx_(&ctx), pairs_(pairs) {
    if (!ctx.limits().timestamps) return;
    const VkQueryPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
                                     .queryType = VK_QUERY_TYPE_TIMESTAMP,
                                     .queryCount = 2 * pairs};
    VkQueryPool pool = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateQueryPool(ctx.device(), &info, nullptr, &pool));
    pool_ = Owned<VkQueryPool>(ctx.device(), pool);
    ctx.name(pool, VK_OBJECT_TYPE_QUERY_POOL, "fird.timer");
}

void GpuTimer::reset(VkCommandBuffer cb) {
    used_ = 0;
    ticks_.clear();
    if (pool_) vkCmdResetQueryPool(cb, pool_.get(), 0, 2 * pairs_);
}

// Both timestamps wait for every earlier command (ALL_COMMANDS): with the passes of one
// command buffer separated by barriers, the begin stamp then marks the end of the pass
// before, not the moment the device's front end reached this command (a top-of-pipe stamp
// would charge a pass for the wait on its predecessor).
std::uint32_t GpuTimer::begin(VkCommandBuffer cb) {
    if (used_ == pairs_) throw std::logic_error("GpuTimer: more passes than the pool has pairs");
    const std::uint32_t pair = used_++;
    if (pool_)
        vkCmdWriteTimestamp2(cb, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_.get(), 2 * pair);
    return pair;
}

void GpuTimer::end(VkCommandBuffer cb, std::uint32_t pair) const {
    if (pool_)
        vkCmdWriteTimestamp2(cb, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_.get(), 2 * pair + 1);
}

void GpuTimer::read() {
    ticks_.assign(2 * std::size_t(used_), 0);
    if (!pool_ || used_ == 0) return;
    FIRD_VK_CHECK(vkGetQueryPoolResults(
        ctx_->device(), pool_.get(), 0, 2 * used_, ticks_.size() * sizeof(std::uint64_t),
        ticks_.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
}

double GpuTimer::elapsed_ms(std::uint32_t pair) const {
    if (!pool_ || 2 * std::size_t(pair) + 1 >= ticks_.size()) return 0.0;
    const std::uint64_t t0 = ticks_[2 * pair], t1 = ticks_[2 * pair + 1];
    return t1 > t0 ? double(t1 - t0) * ctx_->limits().timestamp_period_ns * 1e-6 : 0.0;
}

} // namespace fird::vk
