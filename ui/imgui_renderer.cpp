#include "imgui_renderer.hpp"

#include <algorithm>
#include <cstddef>

#include "imgui_frag.h"
#include "imgui_vert.h"
#include "vk/check.hpp"

namespace fird::ui {

ImGuiRenderer::ImGuiRenderer(const vk::Context& ctx, std::uint32_t frames)
    : ctx_(&ctx), slots_(std::max(1u, frames)) {
    // record() draws each command at its VtxOffset, so a window may hold more than the 65,536
    // vertices 16-bit indices reach: ImGui then splits its draw list at that bound instead of
    // asserting (a freeform search's progress chart and its heights' charts, a dot for each
    // of thousands of candidates, passed it).
    ImGui::GetIO().BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    ImGui::GetIO().Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    font_ = vk::Texture(ctx, std::uint32_t(w), std::uint32_t(h), "fird.imgui.font");
    font_.upload(ctx, pixels);
    ImGui::GetIO().Fonts->SetTexID(static_cast<ImTextureID>(&font_));
}

const vk::GraphicsPipeline& ImGuiRenderer::pipeline_for(VkFormat format) {
    auto it = pipelines_.find(format);
    if (it != pipelines_.end()) return it->second;
    const VkVertexInputAttributeDescription attributes[] = {{.location = 0,
                                                             .binding = 0,
                                                             .format = VK_FORMAT_R32G32_SFLOAT,
                                                             .offset = offsetof(ImDrawVert, pos)},
                                                            {.location = 1,
                                                             .binding = 0,
                                                             .format = VK_FORMAT_R32G32_SFLOAT,
                                                             .offset = offsetof(ImDrawVert, uv)},
                                                            {.location = 2,
                                                             .binding = 0,
                                                             .format = VK_FORMAT_R8G8B8A8_UNORM,
                                                             .offset = offsetof(ImDrawVert, col)}};
    const VkDescriptorType sampler = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    return pipelines_
        .emplace(format, vk::make_graphics_pipeline(
                             *ctx_, {.vertex_spirv = fird_spv_imgui_vert,
                                     .fragment_spirv = fird_spv_imgui_frag,
                                     .push_stages = VK_SHADER_STAGE_VERTEX_BIT,
                                     .push_bytes = sizeof(float) * 4,
                                     .vertex_stride = sizeof(ImDrawVert),
                                     .attributes = attributes,
                                     .depth_compare = VK_COMPARE_OP_ALWAYS,
                                     .colour_formats = std::span(&format, 1),
                                     .blend = vk::kAlphaBlend,
                                     .name = "fird.imgui",
                                     .fragment_descriptors = std::span(&sampler, 1)}))
        .first->second;
}

void ImGuiRenderer::record(VkCommandBuffer cb, const ImDrawData* dd, VkImageView target,
                           VkFormat format, VkExtent2D extent, std::uint32_t slot_index,
                           const ImVec4& clear) {
    const vk::GraphicsPipeline& p = pipeline_for(format);
    Slot& slot = slots_[slot_index % slots_.size()];
    // Copy every list's vertices and indices into this frame's buffers.
    const auto vbytes =
        std::max<std::size_t>(std::size_t(dd->TotalVtxCount) * sizeof(ImDrawVert), 64);
    const auto ibytes =
        std::max<std::size_t>(std::size_t(dd->TotalIdxCount) * sizeof(ImDrawIdx), 64);
    if (slot.vertices.size() < vbytes)
        slot.vertices = vk::Buffer(*ctx_, vbytes * 2, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                   vk::MemoryUse::Upload, "fird.imgui.vertices");
    if (slot.indices.size() < ibytes)
        slot.indices = vk::Buffer(*ctx_, ibytes * 2, VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                  vk::MemoryUse::Upload, "fird.imgui.indices");
    auto* vdst = static_cast<ImDrawVert*>(slot.vertices.data());
    auto* idst = static_cast<ImDrawIdx*>(slot.indices.data());
    for (int n = 0; n < dd->CmdListsCount; ++n) {
        const ImDrawList* list = dd->CmdLists[n];
        std::copy(list->VtxBuffer.begin(), list->VtxBuffer.end(), vdst);
        std::copy(list->IdxBuffer.begin(), list->IdxBuffer.end(), idst);
        vdst += list->VtxBuffer.Size;
        idst += list->IdxBuffer.Size;
    }

    const VkRenderingAttachmentInfo colour{
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = target,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue = {.color = {{clear.x, clear.y, clear.z, clear.w}}}};
    const VkRenderingInfo rendering{.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                                    .renderArea = {{0, 0}, extent},
                                    .layerCount = 1,
                                    .colorAttachmentCount = 1,
                                    .pColorAttachments = &colour};
    vkCmdBeginRendering(cb, &rendering);
    const VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0, 1};
    vkCmdSetViewport(cb, 0, 1, &viewport);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipeline.get());
    const VkBuffer vb = slot.vertices.get();
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cb, 0, 1, &vb, &offset);
    vkCmdBindIndexBuffer(cb, slot.indices.get(), 0,
                         sizeof(ImDrawIdx) == 2 ? VK_INDEX_TYPE_UINT16 : VK_INDEX_TYPE_UINT32);
    // Pixels of the display rectangle to clip space.
    const float push[4] = {2.0f / dd->DisplaySize.x, 2.0f / dd->DisplaySize.y,
                           -1.0f - dd->DisplayPos.x * 2.0f / dd->DisplaySize.x,
                           -1.0f - dd->DisplayPos.y * 2.0f / dd->DisplaySize.y};
    vkCmdPushConstants(cb, p.layout.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), push);
    const ImVec2 scale = dd->FramebufferScale, origin = dd->DisplayPos;
    std::int32_t vtx_base = 0;
    std::uint32_t idx_base = 0;
    for (int n = 0; n < dd->CmdListsCount; ++n) {
        const ImDrawList* list = dd->CmdLists[n];
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) continue; // FIRD's panels register none
            const float x0 = std::max(0.0f, (cmd.ClipRect.x - origin.x) * scale.x);
            const float y0 = std::max(0.0f, (cmd.ClipRect.y - origin.y) * scale.y);
            const float x1 = std::min(float(extent.width), (cmd.ClipRect.z - origin.x) * scale.x);
            const float y1 = std::min(float(extent.height), (cmd.ClipRect.w - origin.y) * scale.y);
            if (x1 <= x0 || y1 <= y0) continue;
            const VkRect2D scissor{{std::int32_t(x0), std::int32_t(y0)},
                                   {std::uint32_t(x1 - x0), std::uint32_t(y1 - y0)}};
            vkCmdSetScissor(cb, 0, 1, &scissor);
            const auto* texture = static_cast<const vk::Texture*>(cmd.TextureId);
            const VkDescriptorImageInfo image{.sampler = texture->sampler(),
                                              .imageView = texture->image().view(),
                                              .imageLayout =
                                                  VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            const VkWriteDescriptorSet write{.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                             .dstBinding = 0,
                                             .descriptorCount = 1,
                                             .descriptorType =
                                                 VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                             .pImageInfo = &image};
            p.push_descriptor_set(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout.get(), 0, 1,
                                  &write);
            vkCmdDrawIndexed(cb, cmd.ElemCount, 1, idx_base + cmd.IdxOffset,
                             vtx_base + std::int32_t(cmd.VtxOffset), 0);
        }
        vtx_base += list->VtxBuffer.Size;
        idx_base += std::uint32_t(list->IdxBuffer.Size);
    }
    vkCmdEndRendering(cb);
}

} // namespace fird::ui
