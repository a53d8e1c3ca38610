// A compute pipeline from embedded SPIR-V whose bindings are pushed per dispatch
// (VK_KHR_push_descriptor), so each pass owns its bindings without descriptor pools.
// Passes use it through vk::TypedPass (typed_pass.hpp), which names the bindings.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "buffer.hpp"
#include "context.hpp"
#include "image.hpp"
#include "owned.hpp"

namespace fird::vk {

// One binding's resource: a storage or uniform buffer (whole), a storage image (GENERAL
// layout), or a uniform or storage texel buffer (a typed view of a buffer, read through
// the texture path or as an image buffer).
struct Binding {
    VkDescriptorType type;
    VkDescriptorBufferInfo buffer{};
    VkDescriptorImageInfo image{};
    VkBufferView texel_view = VK_NULL_HANDLE;
};
inline Binding storage(const Buffer& b) {
    return {.type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .buffer = {.buffer = b.get(), .offset = 0, .range = VK_WHOLE_SIZE}};
}
inline Binding storage(const Image& i) {
    return {.type = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
            .image = {.imageView = i.view(), .imageLayout = VK_IMAGE_LAYOUT_GENERAL}};
}

// A uniform buffer (whole): what every invocation reads at the same address. CPU drivers
// load a storage buffer inside divergent control flow lane by lane, even at a uniform
// address; a uniform buffer's load stays one scalar load (SceneParams: docs/architecture.md,
// "The scene's parameters as a uniform buffer").
inline Binding uniform(const Buffer& b) {
    return {.type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
            .buffer = {.buffer = b.get(), .offset = 0, .range = VK_WHOLE_SIZE}};
}

// A texel view read (or written) as an image buffer: the buffer needs
// VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT.
inline Binding storage_texel(const TexelView& v) {
    return {.type = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, .texel_view = v.get()};
}
inline Binding texel(const TexelView& v) {
    return {.type = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, .texel_view = v.get()};
}

class ComputePipeline {
  public:
    ComputePipeline() = default;
    // binding_types[i] is the descriptor type at binding i of set 0; specialization[i]
    // is the value of the 32-bit specialization constant with constant_id i.
    ComputePipeline(const Context& ctx, std::span<const std::uint32_t> spirv,
                    std::span<const VkDescriptorType> binding_types,
                    std::uint32_t push_constant_bytes, std::string_view name,
                    std::span<const std::uint32_t> specialization = {});

    // Binds the pipeline, pushes bindings 0..n-1 and the push constants, dispatches.
    void dispatch(VkCommandBuffer cb, std::span<const Binding> bindings, const void* push,
                  std::uint32_t groups_x, std::uint32_t groups_y = 1,
                  std::uint32_t groups_z = 1) const;
    // The same, with the group counts read by the device from `args` at `offset` (a
    // VkDispatchIndirectCommand written by an earlier pass; the buffer needs
    // VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT). Counts of 0 dispatch nothing; counts past
    // maxComputeWorkGroupCount are the writer's to prevent.
    void dispatch_indirect(VkCommandBuffer cb, std::span<const Binding> bindings, const void* push,
                           const Buffer& args, VkDeviceSize offset) const;

  private:
    void bind(VkCommandBuffer cb, std::span<const Binding> bindings, const void* push) const;
    Owned<VkDescriptorSetLayout> set_layout_;
    Owned<VkPipelineLayout> layout_;
    Owned<VkPipeline> pipeline_;
    std::vector<VkDescriptorType> types_;
    std::uint32_t push_bytes_ = 0;
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_set_ = nullptr;
};

} // namespace fird::vk
