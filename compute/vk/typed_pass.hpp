// A compute pass that owns its bindings by name: its pipeline, a bindings struct whose
// members name what the shader binds, and its push-constant struct. The struct's fields()
// place each member at the shader's own binding constant (fird_shared.h) with its
// descriptor type, one table from which the pipeline's layout and every dispatch's slots
// are both made: a member cannot land in another slot, a slot cannot be left out or filled
// twice, and a pass given another's push constants does not compile.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include "compute_pipeline.hpp"

namespace fird::vk {

// One member of a bindings struct B: its binding slot, its descriptor type, the member.
template <typename B> struct BindingField {
    std::uint32_t slot;
    VkDescriptorType type;
    Binding B::*member;
};

// For passes without push constants.
struct NoPush {};

template <typename Bindings, typename Push = NoPush> class TypedPass {
  public:
    static constexpr std::size_t kCount = Bindings::fields().size();

    TypedPass() = default;
    TypedPass(const Context& ctx, std::span<const std::uint32_t> spirv, std::string_view name,
              std::span<const std::uint32_t> specialization = {})
        : pipeline_(ctx, spirv, kTypes, kPushBytes, name, specialization) {}

    void dispatch(VkCommandBuffer cb, const Bindings& b, const Push& push, std::uint32_t groups_x,
                  std::uint32_t groups_y = 1, std::uint32_t groups_z = 1) const {
        const auto slots = in_slots(b);
        pipeline_.dispatch(cb, slots, push_data(push), groups_x, groups_y, groups_z);
    }
    // The group counts read by the device from `args` at `offset` (ComputePipeline's).
    void dispatch_indirect(VkCommandBuffer cb, const Bindings& b, const Push& push,
                           const Buffer& args, VkDeviceSize offset) const {
        const auto slots = in_slots(b);
        pipeline_.dispatch_indirect(cb, slots, push_data(push), args, offset);
    }

  private:
    static_assert(std::is_trivially_copyable_v<Push>, "push constants are copied as bytes");
    static constexpr std::uint32_t kPushBytes =
        std::is_same_v<Push, NoPush> ? 0u : std::uint32_t(sizeof(Push));

    // Every slot 0 .. kCount-1 named once (a compile-time check of the table).
    static constexpr std::array<VkDescriptorType, kCount> make_types() {
        std::array<VkDescriptorType, kCount> types{};
        std::array<bool, kCount> named{};
        for (const auto& f : Bindings::fields()) {
            if (f.slot >= kCount || named[f.slot])
                throw std::logic_error("a binding slot outside the pass or named twice");
            named[f.slot] = true;
            types[f.slot] = f.type;
        }
        return types;
    }
    static constexpr std::array<VkDescriptorType, kCount> kTypes = make_types();

    // The members in slot order; a member of the wrong kind (a buffer where the shader
    // reads a texel view, say) is a logic error, not a validation message later.
    static std::array<Binding, kCount> in_slots(const Bindings& b) {
        std::array<Binding, kCount> slots{};
        for (const auto& f : Bindings::fields()) {
            slots[f.slot] = b.*f.member;
            if (slots[f.slot].type != f.type)
                throw std::logic_error("a pass's binding is not of the kind its shader reads");
        }
        return slots;
    }
    static const void* push_data(const Push& push) {
        return kPushBytes ? static_cast<const void*>(&push) : nullptr;
    }

    ComputePipeline pipeline_;
};

} // namespace fird::vk
