#include "reduce_pass.hpp"

#include <stdexcept>
#include <vector>

#include "fird_shared.h"
#include "reduce_sum_comp.h"

namespace fird {

namespace {
constexpr std::uint32_t kSpan = gpu::kReduceWorkgroupSize * gpu::kReduceItemsPerThread;
// reduce_sum.comp sums a thread's items in runs of four.
static_assert(gpu::kReduceItemsPerThread % 4 == 0);
std::uint32_t groups_for(std::uint32_t count) {
    return (count + kSpan - 1) / kSpan;
}
} // namespace

namespace {
ReducePass::Pipeline reduce_pipeline(const vk::Context& ctx, std::uint32_t mode, const char* name) {
    const std::uint32_t spec[] = {mode}; // FIRD_SPEC_REDUCE_MODE
    return ReducePass::Pipeline(ctx, fird_spv_reduce_sum_comp, name, spec);
}
} // namespace

ReducePass::ReducePass(const vk::Context& ctx)
    : pipelines_{reduce_pipeline(ctx, gpu::kReduceSum, "fird.reduce_sum"),
                 reduce_pipeline(ctx, gpu::kReduceSquaredDifference, "fird.reduce_sum.l2"),
                 reduce_pipeline(ctx, gpu::kReduceCandelaSquaredDifference,
                                 "fird.reduce_sum.candela_l2")} {}

// Storage-buffer offsets must respect minStorageBufferOffsetAlignment (<= 256 by spec).
static VkDeviceSize align_offset(VkDeviceSize bytes) {
    return (bytes + 255) / 256 * 256;
}

std::uint64_t ReducePass::scratch_floats(std::uint64_t count) {
    // Partial sums of every level but the last, laid end to end at aligned offsets.
    VkDeviceSize total = 0;
    for (std::uint64_t n = count; n > 1;) {
        n = (n + kSpan - 1) / kSpan;
        if (n > 1) total = align_offset(total + n * sizeof(float));
    }
    return total / sizeof(float) + 1;
}

void ReducePass::record(VkCommandBuffer cb, const FloatTable& a, const FloatTable* b,
                        std::uint32_t count, const FloatTable& scratch, const vk::Buffer& result,
                        VkDeviceSize result_offset, ReduceDifference difference) const {
    bool weighted = b && difference.metric == FarFieldMetric::CandelaL2;
    if (weighted && (difference.width == 0 || count % difference.width != 0))
        throw std::invalid_argument("ReducePass: a weighted difference needs the grid's width");
    if (weighted && (!difference.row_weights || difference.row_weights->values.size() <
                                                    (count / difference.width) * sizeof(float)))
        throw std::invalid_argument("ReducePass: a weighted difference needs a weight per row");
    // The views are read without robustness: a short table would be read past its end.
    if (a.values.size() < VkDeviceSize(count) * sizeof(float) ||
        (b && b->values.size() < VkDeviceSize(count) * sizeof(float)))
        throw std::invalid_argument("ReducePass: an input holds fewer values than the count");
    if (scratch.values.size() < scratch_floats(count) * sizeof(float))
        throw std::invalid_argument("ReducePass: the scratch is smaller than scratch_floats");
    // Level 0 reads a (and b); later levels read the previous level's partials, placed one
    // after another in scratch at aligned offsets, through the scratch's view from the
    // level's first float (ReducePush::a_offset), while the level writes its own partials
    // past them (the partials' binding at its offset).
    const FloatTable* input = &a;
    VkDeviceSize input_offset = 0;
    VkDeviceSize scratch_offset = 0;
    std::uint32_t n = count;
    std::uint32_t mode = weighted ? gpu::kReduceCandelaSquaredDifference
                         : b      ? gpu::kReduceSquaredDifference
                                  : gpu::kReduceSum;
    do {
        const std::uint32_t groups = groups_for(n);
        const bool last = groups <= 1;
        vk::Binding out = vk::storage(last ? result : scratch.values);
        out.buffer.offset = last ? result_offset : scratch_offset;
        const ReduceBindings bindings{
            .a = vk::storage_texel(input->texels),
            .b = vk::storage_texel(b ? b->texels : input->texels),
            .partial = out,
            .row_weight =
                vk::storage_texel(weighted ? difference.row_weights->texels : input->texels)};
        const gpu::ReducePush push{.count = n,
                                   .width = weighted ? difference.width : 1u,
                                   .height = weighted ? count / difference.width : 1u,
                                   .a_offset = std::uint32_t(input_offset / sizeof(float))};
        pipelines_.at(mode).dispatch(cb, bindings, push, groups > 0 ? groups : 1);
        vk::barrier_all(cb);
        input = &scratch;
        input_offset = scratch_offset;
        scratch_offset = align_offset(scratch_offset + groups * sizeof(float));
        n = groups;
        mode = gpu::kReduceSum;
        b = nullptr;
        weighted = false;
        if (last) break;
    } while (true);
}

FloatTable metric_row_weights(const vk::Context& ctx, FarFieldMetric metric, std::uint32_t width,
                              std::uint32_t height) {
    std::vector<float> w(height);
    for (std::uint32_t row = 0; row < height; ++row)
        w[row] = float(metric_cell_weight(metric, row, width, height));
    FloatTable out =
        make_float_table(ctx, w.size(), vk::MemoryUse::Device, "fird.reduce.row_weights");
    out.values.upload(ctx, std::span<const float>(w));
    return out;
}

double ReducePass::run(const vk::Context& ctx, const FloatTable& a, const FloatTable* b,
                       std::uint32_t count, ReduceDifference difference) const {
    FloatTable row_weights;
    if (b && difference.metric != FarFieldMetric::L2 && !difference.row_weights &&
        difference.width > 0) {
        row_weights =
            metric_row_weights(ctx, difference.metric, difference.width, count / difference.width);
        difference.row_weights = &row_weights;
    }
    const FloatTable scratch =
        make_float_table(ctx, scratch_floats(count), vk::MemoryUse::Device, "fird.reduce.scratch");
    vk::Buffer result(ctx, sizeof(float), vk::kStorageUsage, vk::MemoryUse::Readback,
                      "fird.reduce.result");
    ctx.submit_and_wait(
        [&](VkCommandBuffer cb) { record(cb, a, b, count, scratch, result, 0, difference); });
    return result.download_as<float>(ctx, 1)[0];
}

double ReducePass::sum(const vk::Context& ctx, const FloatTable& a, std::uint32_t count) const {
    return run(ctx, a, nullptr, count, {});
}

double ReducePass::sum_squared_difference(const vk::Context& ctx, const FloatTable& a,
                                          const FloatTable& b, std::uint32_t count,
                                          ReduceDifference difference) const {
    return run(ctx, a, &b, count, difference);
}

} // namespace fird
