// FIRD's own renderer for Dear ImGui's draw data. Debian's Dear ImGui is 1.86, whose
// Vulkan backend binds no user textures (ImGui_ImplVulkan_AddTexture came in 1.87); this
// one does: an ImTextureID is a vk::Texture*, so the viewport, the far fields and the
// plots are ImGui::Image()s like any other widget. It renders with dynamic rendering into
// any colour image view — a swapchain image or an offscreen target — so the whole frame
// also renders with no window at all (fird screenshot --view workbench).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include <imgui.h>

#include "vk/buffer.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/image.hpp"

namespace fird::ui {

class ImGuiRenderer {
  public:
    // Builds the font atlas of the current ImGui context into a texture.
    ImGuiRenderer(const vk::Context& ctx, std::uint32_t frames_in_flight);

    // Records the draw data into `target` (in COLOR_ATTACHMENT_OPTIMAL layout), clearing
    // it first. `slot` picks the per-frame vertex buffers (a frame in flight keeps its own).
    void record(VkCommandBuffer cb, const ImDrawData* data, VkImageView target, VkFormat format,
                VkExtent2D extent, std::uint32_t slot, const ImVec4& clear);

  private:
    const vk::GraphicsPipeline& pipeline_for(VkFormat format);
    const vk::Context* ctx_;
    vk::Texture font_;
    std::map<VkFormat, vk::GraphicsPipeline> pipelines_;
    struct Slot {
        vk::Buffer vertices, indices;
    };
    std::vector<Slot> slots_;
};

} // namespace fird::ui
