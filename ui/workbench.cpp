#include "workbench.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#define GLFW_INCLUDE_NONE
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "report/device_report.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"

namespace fird::ui {

namespace {

void check_imgui_vk(VkResult r) {
    if (r < 0) vk::throw_vk_error("ImGui_ImplVulkan", r);
}

struct Glfw {
    Glfw() {
        if (!glfwInit())
            throw std::runtime_error("cannot open a window: no display (GLFW init failed)");
    }
    ~Glfw() { glfwTerminate(); }
    Glfw(const Glfw&) = delete;
    Glfw& operator=(const Glfw&) = delete;
};

void render_frame(const vk::Context& ctx, ImGui_ImplVulkanH_Window& wd, ImDrawData* draw_data,
                  bool& rebuild) {
    const VkDevice dev = ctx.device();
    VkSemaphore acquired = wd.FrameSemaphores[wd.SemaphoreIndex].ImageAcquiredSemaphore;
    VkSemaphore done = wd.FrameSemaphores[wd.SemaphoreIndex].RenderCompleteSemaphore;
    VkResult r = vkAcquireNextImageKHR(dev, wd.Swapchain, UINT64_MAX, acquired, VK_NULL_HANDLE,
                                       &wd.FrameIndex);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        rebuild = true;
        return;
    }
    FIRD_VK_CHECK(r);
    ImGui_ImplVulkanH_Frame& fd = wd.Frames[wd.FrameIndex];
    FIRD_VK_CHECK(vkWaitForFences(dev, 1, &fd.Fence, VK_TRUE, UINT64_MAX));
    FIRD_VK_CHECK(vkResetFences(dev, 1, &fd.Fence));
    FIRD_VK_CHECK(vkResetCommandPool(dev, fd.CommandPool, 0));
    const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                         .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FIRD_VK_CHECK(vkBeginCommandBuffer(fd.CommandBuffer, &begin));
    const VkRenderPassBeginInfo rp{
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = wd.RenderPass,
        .framebuffer = fd.Framebuffer,
        .renderArea = {{0, 0}, {std::uint32_t(wd.Width), std::uint32_t(wd.Height)}},
        .clearValueCount = 1,
        .pClearValues = &wd.ClearValue};
    vkCmdBeginRenderPass(fd.CommandBuffer, &rp, VK_SUBPASS_CONTENTS_INLINE);
    ImGui_ImplVulkan_RenderDrawData(draw_data, fd.CommandBuffer);
    vkCmdEndRenderPass(fd.CommandBuffer);
    FIRD_VK_CHECK(vkEndCommandBuffer(fd.CommandBuffer));
    const VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    const VkSubmitInfo submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                              .waitSemaphoreCount = 1,
                              .pWaitSemaphores = &acquired,
                              .pWaitDstStageMask = &wait_stage,
                              .commandBufferCount = 1,
                              .pCommandBuffers = &fd.CommandBuffer,
                              .signalSemaphoreCount = 1,
                              .pSignalSemaphores = &done};
    FIRD_VK_CHECK(vkQueueSubmit(ctx.queue(), 1, &submit, fd.Fence));
    const VkPresentInfoKHR present{.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                                   .waitSemaphoreCount = 1,
                                   .pWaitSemaphores = &done,
                                   .swapchainCount = 1,
                                   .pSwapchains = &wd.Swapchain,
                                   .pImageIndices = &wd.FrameIndex};
    r = vkQueuePresentKHR(ctx.queue(), &present);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        rebuild = true;
        return;
    }
    FIRD_VK_CHECK(r);
    wd.SemaphoreIndex = (wd.SemaphoreIndex + 1) % wd.ImageCount;
}

void device_panel(const nlohmann::json& report) {
    ImGui::Begin("Device");
    ImGui::TextUnformatted(device_report_text(report).c_str());
    ImGui::End();
}

} // namespace

int run_workbench(const WorkbenchOptions& options) {
    const Glfw glfw;
    if (!glfwVulkanSupported()) throw std::runtime_error("GLFW finds no Vulkan loader");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    GLFWwindow* window = glfwCreateWindow(1280, 800, "FIRD workbench", nullptr, nullptr);
    if (!window) throw std::runtime_error("cannot create the workbench window");

    std::uint32_t ext_count = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
    vk::ContextOptions ctx_options{.validation = options.validation,
                                   .device_name = options.device_name,
                                   .device_extensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME}};
    for (std::uint32_t i = 0; i < ext_count; ++i)
        ctx_options.instance_extensions.emplace_back(exts[i]);
    const auto ctx = vk::Context::create(ctx_options);
    const auto report = device_report(ctx);

    VkSurfaceKHR surface = VK_NULL_HANDLE;
    FIRD_VK_CHECK(glfwCreateWindowSurface(ctx.instance(), window, nullptr, &surface));
    VkBool32 can_present = VK_FALSE;
    FIRD_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physical_device(), ctx.queue_family(),
                                                       surface, &can_present));
    if (!can_present) throw std::runtime_error("the chosen device cannot present to this window");

    ImGui_ImplVulkanH_Window wd;
    wd.Surface = surface;
    const VkFormat formats[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM};
    wd.SurfaceFormat = ImGui_ImplVulkanH_SelectSurfaceFormat(
        ctx.physical_device(), surface, formats, 2, VK_COLORSPACE_SRGB_NONLINEAR_KHR);
    const VkPresentModeKHR modes[] = {VK_PRESENT_MODE_FIFO_KHR};
    wd.PresentMode = ImGui_ImplVulkanH_SelectPresentMode(ctx.physical_device(), surface, modes, 1);
    int width = 0;
    int height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    constexpr std::uint32_t kMinImages = 2;
    ImGui_ImplVulkanH_CreateOrResizeWindow(ctx.instance(), ctx.physical_device(), ctx.device(), &wd,
                                           ctx.queue_family(), nullptr, width, height, kMinImages);

    const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 64};
    const VkDescriptorPoolCreateInfo pool_info{
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT,
        .maxSets = 64,
        .poolSizeCount = 1,
        .pPoolSizes = &pool_size};
    VkDescriptorPool pool = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateDescriptorPool(ctx.device(), &pool_info, nullptr, &pool));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;
    ImGui_ImplGlfw_InitForVulkan(window, true);
    ImGui_ImplVulkan_InitInfo init{};
    init.Instance = ctx.instance();
    init.PhysicalDevice = ctx.physical_device();
    init.Device = ctx.device();
    init.QueueFamily = ctx.queue_family();
    init.Queue = ctx.queue();
    init.DescriptorPool = pool;
    init.MinImageCount = kMinImages;
    init.ImageCount = wd.ImageCount;
    init.CheckVkResultFn = check_imgui_vk;
    ImGui_ImplVulkan_Init(&init, wd.RenderPass);
    ctx.submit_and_wait([](VkCommandBuffer cb) { ImGui_ImplVulkan_CreateFontsTexture(cb); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();

    bool rebuild = false;
    for (std::uint32_t frame = 0; !glfwWindowShouldClose(window); ++frame) {
        if (options.max_frames && frame >= options.max_frames) break;
        glfwPollEvents();
        if (rebuild) {
            glfwGetFramebufferSize(window, &width, &height);
            if (width > 0 && height > 0) {
                ImGui_ImplVulkan_SetMinImageCount(kMinImages);
                ImGui_ImplVulkanH_CreateOrResizeWindow(ctx.instance(), ctx.physical_device(),
                                                       ctx.device(), &wd, ctx.queue_family(),
                                                       nullptr, width, height, kMinImages);
                wd.FrameIndex = 0;
                rebuild = false;
            }
        }
        ImGui_ImplVulkan_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        device_panel(report);
        ImGui::Render();
        ImDrawData* draw_data = ImGui::GetDrawData();
        if (draw_data->DisplaySize.x > 0 && draw_data->DisplaySize.y > 0)
            render_frame(ctx, wd, draw_data, rebuild);
    }

    FIRD_VK_CHECK(vkDeviceWaitIdle(ctx.device()));
    ImGui_ImplVulkan_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    ImGui_ImplVulkanH_DestroyWindow(ctx.instance(), ctx.device(), &wd, nullptr);
    vkDestroyDescriptorPool(ctx.device(), pool, nullptr);
    glfwDestroyWindow(window);
    return ctx.validation_errors() == 0 ? 0 : 1;
}

} // namespace fird::ui
