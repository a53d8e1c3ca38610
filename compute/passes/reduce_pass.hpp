// Device reduction: the sum of a float buffer, or the sum of squared differences of
// two (the l2 distance's radicand), without reading the inputs back.
#pragma once

#include <array>
#include <cstdint>

#include "farfield/farfield.hpp"
#include "fird_shared.h"
#include "passes/float_table.hpp"
#include "vk/buffer.hpp"
#include "vk/typed_pass.hpp"

namespace fird {

// How a reduction's difference is weighted: a far-field metric over a grid of `width`
// columns (count / width rows), each row's weight read from `row_weights`
// (metric_row_weights; the convenience calls make them when null, record() needs them);
// L2 needs no grid.
struct ReduceDifference {
    FarFieldMetric metric = FarFieldMetric::L2;
    std::uint32_t width = 0;
    const FloatTable* row_weights = nullptr;
};

// metric_cell_weight of each row of a width x height far field, computed in double and
// stored as floats in a device table, for ReduceDifference::row_weights.
FloatTable metric_row_weights(const vk::Context& ctx, FarFieldMetric metric, std::uint32_t width,
                              std::uint32_t height);

// reduce_sum.comp's bindings by name (vk::TypedPass): the inputs' texel views (b unused by
// a plain sum), the level's partial sums, and the rows' metric weights (weighted
// differences).
struct ReduceBindings {
    vk::Binding a, b, partial, row_weight;
    static constexpr auto fields() {
        using B = ReduceBindings;
        constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        constexpr VkDescriptorType kTexel = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        return std::array<vk::BindingField<B>, 4>{{
            {gpu::kReduceBindingA, kTexel, &B::a},
            {gpu::kReduceBindingB, kTexel, &B::b},
            {gpu::kReduceBindingPartial, kStorage, &B::partial},
            {gpu::kReduceBindingRowWeight, kTexel, &B::row_weight},
        }};
    }
};

class ReducePass {
  public:
    using Pipeline = vk::TypedPass<ReduceBindings, gpu::ReducePush>;
    explicit ReducePass(const vk::Context& ctx);

    // Floats of scratch needed to reduce `count` values.
    static std::uint64_t scratch_floats(std::uint64_t count);

    // Records the passes; the result lands in result at result_offset (bytes, a multiple of
    // 256: storage-buffer offsets are aligned). `b` may be null for a plain sum. scratch
    // must hold scratch_floats(count); result may alias nothing else.
    void record(VkCommandBuffer cb, const FloatTable& a, const FloatTable* b, std::uint32_t count,
                const FloatTable& scratch, const vk::Buffer& result, VkDeviceSize result_offset = 0,
                ReduceDifference difference = {}) const;

    // Convenience: allocate scratch, run, read back.
    double sum(const vk::Context& ctx, const FloatTable& a, std::uint32_t count) const;
    double sum_squared_difference(const vk::Context& ctx, const FloatTable& a, const FloatTable& b,
                                  std::uint32_t count, ReduceDifference difference = {}) const;

  private:
    double run(const vk::Context& ctx, const FloatTable& a, const FloatTable* b,
               std::uint32_t count, ReduceDifference difference) const;
    std::array<Pipeline, 3> pipelines_; // by mode (gpu::kReduceSum, ...)
};

} // namespace fird
