// The frame loop, in a window or offscreen. Layout: panels (panel_*.cpp) on plain state
// (workbench_state), compute in the Worker, drawing by FIRD's ImGui renderer.
#include "workbench.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <thread>

#define GLFW_INCLUDE_NONE
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>
#include <nlohmann/json.hpp>

#include "imgui_renderer.hpp"
#include "offscreen_target.hpp"
#include "panels.hpp"
#include "run_directory.hpp"
#include "script.hpp"
#include "settings.hpp"
#include "views.hpp"
#include "vk/check.hpp"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"
#include "vk/submission.hpp"

namespace fird::ui {

namespace {

// Rays per submission while the window shares the device with the worker: Model A traces
// 2^17 rays in ~15 ms on 2 lavapipe cores, so a frame waits at most about that long for
// the compute work queued before it (docs/workbench.md, Measured).
constexpr std::uint64_t kWorkbenchBatchRays = 1ull << 17;

const ImVec4 kClear{0.12f, 0.12f, 0.14f, 1.0f};

struct Glfw {
    Glfw() {
        if (!glfwInit())
            throw std::runtime_error("cannot open a window: no display (GLFW init failed)");
    }
    ~Glfw() { glfwTerminate(); }
    Glfw(const Glfw&) = delete;
    Glfw& operator=(const Glfw&) = delete;
};

struct ImGuiScope {
    ImGuiScope() {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::StyleColorsDark();
    }
    ~ImGuiScope() { ImGui::DestroyContext(); }
    ImGuiScope(const ImGuiScope&) = delete;
    ImGuiScope& operator=(const ImGuiScope&) = delete;
};

// What one frame works with, beside the window.
struct Session {
    Session(const vk::Context& c) : ctx(c), worker(c), renderer(c) {}
    const vk::Context& ctx;
    Worker worker;
    // Before the state: the state's redraws in flight use the renderer's pipeline and
    // buffers, and are waited for when the state goes.
    render::ViewportRenderer renderer;
    WorkbenchState state;

    Frame frame() {
        for (std::string& line : worker.take_log())
            add_log(state, std::move(line));
        return Frame{ctx, worker, state, renderer, worker.snapshot(), worker.picked()};
    }
};

// Records the frame's draw data into `target` (left ready to copy). `slot`: the
// renderer's buffers to use, none a frame still in flight may read.
void record_into(VkCommandBuffer cb, ImGuiRenderer& renderer, const ImDrawData* data,
                 const render::OffscreenTarget& target, std::uint32_t slot) {
    vk::transition(cb, target.colour(), VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    renderer.record(cb, data, target.colour().view(), render::kColourFormat,
                    {target.width(), target.height()}, slot, kClear);
    vk::transition(cb, target.colour(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

// The frame's draw data into an offscreen RGBA8 image, read back (a screenshot).
std::vector<std::uint8_t> draw_offscreen(const vk::Context& ctx, ImGuiRenderer& renderer,
                                         const ImDrawData* data, std::uint32_t w, std::uint32_t h,
                                         std::uint32_t slot) {
    const render::OffscreenTarget target(ctx, w, h, "fird.workbench.offscreen");
    ctx.submit_and_wait([&](VkCommandBuffer cb) { record_into(cb, renderer, data, target, slot); });
    return target.read_rgba(ctx);
}

// A frame of `fird gui --offscreen`: drawn into `target` on the frames' queue and waited
// for; nothing is read back.
void draw_frame_offscreen(const vk::Context& ctx, ImGuiRenderer& renderer, const ImDrawData* data,
                          const render::OffscreenTarget& target) {
    const vk::Submission frame(
        ctx, [&](VkCommandBuffer cb) { record_into(cb, renderer, data, target, 0); },
        "fird.workbench.frame");
    frame.wait();
}

void present(const vk::Context& ctx, ImGui_ImplVulkanH_Window& wd, ImGuiRenderer& renderer,
             const ImDrawData* data, bool& rebuild) {
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
    // What the work queue wrote (the font, when the worker has a queue of its own) reached
    // the host's fence wait available; this makes it visible to the frame's reads.
    vk::barrier_all(fd.CommandBuffer);
    vk::transition(fd.CommandBuffer, fd.Backbuffer, VK_IMAGE_ASPECT_COLOR_BIT,
                   VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    renderer.record(fd.CommandBuffer, data, fd.BackbufferView, wd.SurfaceFormat.format,
                    {std::uint32_t(wd.Width), std::uint32_t(wd.Height)}, wd.FrameIndex, kClear);
    vk::transition(fd.CommandBuffer, fd.Backbuffer, VK_IMAGE_ASPECT_COLOR_BIT,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
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
    const VkPresentInfoKHR info{.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                                .waitSemaphoreCount = 1,
                                .pWaitSemaphores = &done,
                                .swapchainCount = 1,
                                .pSwapchains = &wd.Swapchain,
                                .pImageIndices = &wd.FrameIndex};
    {
        const auto queue = ctx.lock_queue(); // the worker too, unless it has a queue of its own
        FIRD_VK_CHECK(vkQueueSubmit(ctx.queue(), 1, &submit, fd.Fence));
        r = vkQueuePresentKHR(ctx.queue(), &info);
    }
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        rebuild = true;
        return;
    }
    FIRD_VK_CHECK(r);
    wd.SemaphoreIndex = (wd.SemaphoreIndex + 1) % wd.ImageCount;
}

// (Re)creates the swapchain. Dear ImGui's helper waits for the device idle, which uses
// every queue: it must not run while the worker submits, so it holds every queue's lock.
void resize_swapchain(const vk::Context& ctx, ImGui_ImplVulkanH_Window& wd, int width, int height,
                      std::uint32_t min_images) {
    const auto queues = ctx.lock_all_queues();
    ImGui_ImplVulkanH_CreateOrResizeWindow(ctx.instance(), ctx.physical_device(), ctx.device(), &wd,
                                           ctx.queue_family(), nullptr, width, height, min_images);
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, std::size_t(q * double(v.size() - 1) + 0.5))];
}

void write_png(const std::string& path, const std::vector<std::uint8_t>& rgba, std::uint32_t w,
               std::uint32_t h) {
    render::write_rgba_png(path, rgba, w, h);
}

} // namespace

// The window of an interactive session: GLFW's, its surface and swapchain, and the files
// dropped on it. None with `fird gui --offscreen`.
struct WindowSurface {
    GLFWwindow* window = nullptr;
    ImGui_ImplVulkanH_Window wd;
    std::vector<std::string> dropped;
};

int run_workbench(const WorkbenchOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    double first_frame_ms = 0.0;
    const bool offscreen = options.offscreen_w > 0 && options.offscreen_h > 0;
    // A script is read (and refused) before anything opens.
    std::optional<ScriptRunner> script;
    if (!options.script.empty()) script.emplace(parse_script(options.script));
    std::optional<Glfw> glfw;
    std::optional<WindowSurface> win;
    // Offscreen, the session starts from the stated defaults and saves nothing: a run
    // without a display is measured the same way on every machine and leaves the user's
    // window and layout alone.
    Settings settings = offscreen ? Settings{} : load_settings();
    vk::ContextOptions ctx_options{.validation = options.validation,
                                   .device_name = options.device_name,
                                   .max_batch_rays = options.max_batch_rays ? options.max_batch_rays
                                                                            : kWorkbenchBatchRays,
                                   .yield_between_passes = true};
    if (!offscreen) {
        glfw.emplace();
        if (!glfwVulkanSupported()) throw std::runtime_error("GLFW finds no Vulkan loader");
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        win.emplace();
        win->window = glfwCreateWindow(settings.window_w, settings.window_h, "FIRD workbench",
                                       nullptr, nullptr);
        if (!win->window) throw std::runtime_error("cannot create the workbench window");
        glfwSetWindowUserPointer(win->window, &win->dropped);
        glfwSetDropCallback(win->window, [](GLFWwindow* w, int count, const char** paths) {
            auto* d = static_cast<std::vector<std::string>*>(glfwGetWindowUserPointer(w));
            for (int i = 0; i < count; ++i)
                d->emplace_back(paths[i]);
        });
        std::uint32_t ext_count = 0;
        const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
        for (std::uint32_t i = 0; i < ext_count; ++i)
            ctx_options.instance_extensions.emplace_back(exts[i]);
        ctx_options.device_extensions.emplace_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    }
    const auto ctx = vk::Context::create(ctx_options);
    // Before the surface, the swapchain and Dear ImGui's GLFW backend, whose teardown the
    // exception from the first pipeline (the session's viewport) would skip.
    vk::require_fragment_shaders(ctx);

    int width = int(options.offscreen_w), height = int(options.offscreen_h);
    constexpr std::uint32_t kMinImages = 2;
    if (win) {
        ImGui_ImplVulkanH_Window& wd = win->wd;
        VkSurfaceKHR surface = VK_NULL_HANDLE;
        FIRD_VK_CHECK(glfwCreateWindowSurface(ctx.instance(), win->window, nullptr, &surface));
        VkBool32 can_present = VK_FALSE;
        FIRD_VK_CHECK(vkGetPhysicalDeviceSurfaceSupportKHR(
            ctx.physical_device(), ctx.queue_family(), surface, &can_present));
        if (!can_present)
            throw std::runtime_error("the chosen device cannot present to this window (fird gui "
                                     "--offscreen WxH runs the workbench without one)");
        wd.Surface = surface;
        const VkFormat formats[] = {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM};
        wd.SurfaceFormat = ImGui_ImplVulkanH_SelectSurfaceFormat(
            ctx.physical_device(), surface, formats, 2, VK_COLORSPACE_SRGB_NONLINEAR_KHR);
        const VkPresentModeKHR modes[] = {VK_PRESENT_MODE_FIFO_KHR};
        wd.PresentMode =
            ImGui_ImplVulkanH_SelectPresentMode(ctx.physical_device(), surface, modes, 1);
        glfwGetFramebufferSize(win->window, &width, &height);
        resize_swapchain(ctx, wd, width, height, kMinImages);
    }
    // Offscreen, the frames' image (a script's `resize` makes a new one), no larger than the
    // device's images may be.
    const auto offscreen_target = [&](int w, int h) {
        const std::uint32_t most = ctx.limits().max_image_dimension_2d;
        if (std::uint32_t(w) > most || std::uint32_t(h) > most)
            throw std::runtime_error(fmt::format(
                "offscreen frames of {} x {}: this device's images are at most {} pixels a side", w,
                h, most));
        return render::OffscreenTarget(ctx, std::uint32_t(w), std::uint32_t(h),
                                       "fird.workbench.frame");
    };
    std::optional<render::OffscreenTarget> target;
    if (offscreen) target.emplace(offscreen_target(width, height));
    std::uint64_t frames_drawn = 0;

    const ImGuiScope imgui;
    // The layout is FIRD's own (ui/layout.hpp, kept in settings.txt): Dear ImGui keeps no
    // window positions of its own.
    ImGui::GetIO().IniFilename = nullptr;
    if (win) {
        float xscale = 1.0f, yscale = 1.0f;
        glfwGetWindowContentScale(win->window, &xscale, &yscale);
        if (xscale > 1.0f) {
            ImGui::GetStyle().ScaleAllSizes(xscale); // HiDPI
            ImGui::GetIO().FontGlobalScale = xscale;
        }
        ImGui_ImplGlfw_InitForVulkan(win->window, true);
    }
    int exit_code = 0;
    std::vector<double> frame_ms;
    // Where a frame's time goes (for --stats): building it (panels, view redraws and their
    // uploads) and submitting and presenting it (which waits behind the worker's compute
    // on a device with one queue).
    std::vector<double> build_ms, present_ms;
    std::uint64_t rays = 0, evaluations = 0;
    // At exit, for --stats: each panel's rectangle and the window in window pixels, the
    // viewport's camera (how a layout or a drag is checked from outside).
    // The sliders' values: where a search's end left them.
    nlohmann::json panels = nlohmann::json::object(), window_size, camera, sliders;
    // The followed folder and the job written last, if any.
    nlohmann::json followed = nullptr, job = nullptr, tolerance = nullptr, cad = nullptr;
    {
        // A slot per swapchain image (offscreen: one for the frames), and one more for the
        // scripts' screenshots.
        const std::uint32_t frame_slots = win ? win->wd.ImageCount : 1;
        ImGuiRenderer renderer(ctx, frame_slots + 1);
        Session session(ctx);
        session.state.recent = settings.recent;
        session.state.layout = settings.layout;
        session.state.runs_dir = settings.runs_dir.empty() ? runs_directory() : settings.runs_dir;
        if (!options.scene.empty()) open_file(session.state, options.scene);
        bool rebuild = false;
        auto last_frame = std::chrono::steady_clock::now();
        for (std::uint32_t n = 0;
             !(win && glfwWindowShouldClose(win->window)) && !session.state.quit; ++n) {
            if (options.max_frames && n >= options.max_frames) break;
            const auto t0 = std::chrono::steady_clock::now();
            if (win) {
                ImGui_ImplVulkanH_Window& wd = win->wd;
                glfwPollEvents();
                for (const std::string& path : std::exchange(win->dropped, {}))
                    open_file(session.state, path);
                glfwGetFramebufferSize(win->window, &width, &height);
                if (width != wd.Width || height != wd.Height) rebuild = true; // resized
                if (rebuild) {
                    glfwGetFramebufferSize(win->window, &width, &height);
                    if (width > 0 && height > 0) {
                        resize_swapchain(ctx, wd, width, height, kMinImages);
                        wd.FrameIndex = 0;
                        rebuild = false;
                    }
                }
                ImGui_ImplGlfw_NewFrame();
            } else {
                // What GLFW's backend sets each frame: the display and the time since the
                // last frame (no mouse but a script's, no keyboard).
                ImGuiIO& io = ImGui::GetIO();
                io.DisplaySize = ImVec2(float(width), float(height));
                io.DeltaTime = std::max(
                    1e-4f,
                    std::chrono::duration<float>(t0 - std::exchange(last_frame, t0)).count());
            }
            if (const ScriptedMouse& m = session.state.scripted_mouse; m.active) {
                // A script's drag plays in place of the window's mouse.
                ImGuiIO& io = ImGui::GetIO();
                io.MousePos = ImVec2(m.x, m.y);
                io.MouseDown[ImGuiMouseButton_Left] = m.left;
                io.MouseDown[ImGuiMouseButton_Right] = m.right;
            }
            ImGui::NewFrame();
            Frame f = session.frame();
            build_frame(f);
            bool more = true;
            if (script) {
                try {
                    const ScriptHost host{
                        .screenshot =
                            [&](const std::string& path) {
                                // The views as they are now: the frame built again with
                                // their redraws waited for.
                                ImGui::Render();
                                ImGui::NewFrame();
                                session.state.wait_for_views = true;
                                Frame current = session.frame();
                                build_frame(current);
                                session.state.wait_for_views = false;
                                ImGui::Render();
                                const ImDrawData* d = ImGui::GetDrawData();
                                const auto w = std::uint32_t(d->DisplaySize.x),
                                           h = std::uint32_t(d->DisplaySize.y);
                                write_png(path, draw_offscreen(ctx, renderer, d, w, h, frame_slots),
                                          w, h);
                                ImGui::NewFrame(); // the frame goes on to the window below
                                Frame again = session.frame();
                                build_frame(again);
                            },
                        .resize =
                            [&](int w, int h) {
                                if (win) {
                                    glfwSetWindowSize(win->window, w, h);
                                    return;
                                }
                                // Made before the old one goes: a size refused leaves
                                // the frames as they were.
                                render::OffscreenTarget resized = offscreen_target(w, h);
                                target.emplace(std::move(resized));
                                width = w;
                                height = h;
                            }};
                    more = script->step(f, host);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "fird: error: %s\n", e.what());
                    exit_code = 1;
                    more = false;
                }
            }
            ImGui::Render();
            const auto built = std::chrono::steady_clock::now();
            const ImDrawData* data = ImGui::GetDrawData();
            if (data->DisplaySize.x > 0 && data->DisplaySize.y > 0) {
                if (win)
                    present(ctx, win->wd, renderer, data, rebuild);
                else if (target && data->DisplaySize.x == float(target->width()) &&
                         data->DisplaySize.y == float(target->height())) {
                    draw_frame_offscreen(ctx, renderer, data, *target);
                    ++frames_drawn;
                }
                // (else: the frame built before a script's resize; the next one is drawn)
            }
            const auto t1 = std::chrono::steady_clock::now();
            frame_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
            build_ms.push_back(std::chrono::duration<double, std::milli>(built - t0).count());
            present_ms.push_back(std::chrono::duration<double, std::milli>(t1 - built).count());
            if (n == 0)
                first_frame_ms = std::chrono::duration<double, std::milli>(t1 - started).count();
            if (script && !more) break;
            // Offscreen frames come at most 60 a second, as a window's on a 60 Hz display:
            // a script's `wait N` frames and its bounds in frames last as long in either
            // (the frame times above leave this wait out).
            if (offscreen) std::this_thread::sleep_until(t0 + std::chrono::microseconds(16667));
        }
        session.worker.stop();
        rays = session.worker.rays_traced();
        evaluations = session.worker.evaluations();
        settings.recent = session.state.recent;
        settings.runs_dir = session.state.runs_dir;
        settings.layout = session.state.layout;
        for (const PanelId id : kPanels) {
            const PanelRect& r = session.state.drawn[std::size_t(id)];
            panels[panel_key(id)] = {r.x, r.y, r.w, r.h};
        }
        window_size = {session.state.display_w, session.state.display_h};
        sliders = session.state.editor.parameters;
        if (const FolderFollow& fw = session.state.follow; !fw.dir.empty())
            followed = {{"dir", fw.dir},
                        {"began", fw.search != nullptr},
                        {"evaluations", fw.search ? fw.search->rows.candidates.size() : 0},
                        {"ended", fw.search && fw.search->end}};
        if (const ToleranceProgress t = session.worker.tolerance(); t.generation > 0)
            tolerance = {{"dir", t.out_dir},
                         {"traced", t.rows.size()},
                         {"ended", t.result.has_value()},
                         {"stopped", t.result && t.result->stopped}};
        if (const auto& r = session.state.cad.report) {
            nlohmann::json files = nlohmann::json::array();
            for (const ExportedFile& file : r->files)
                files.push_back(file.name);
            cad = {{"dir", session.state.cad.written_dir},
                   {"files", files},
                   {"exact", r->exact},
                   {"creased", r->creased},
                   {"bend_radius_mm",
                    r->bend ? nlohmann::json(r->bend->radius_mm) : nlohmann::json(nullptr)}};
        }
        if (const auto& w = session.state.cluster.written)
            job = {{"scene", w->scene}, {"run_sh", w->run_sh}, {"slurm_sh", w->slurm_sh}};
        const render::OrbitCamera& c = session.state.viewport.camera;
        camera = {{"azimuth_deg", c.azimuth_deg},
                  {"elevation_deg", c.elevation_deg},
                  {"distance_mm", c.distance_mm},
                  {"target_mm", {c.target.x, c.target.y, c.target.z}}};
        {
            // The worker may still be finishing a submission: waiting for the device uses
            // every queue, so it takes every queue's lock like a submission does.
            const auto queues = ctx.lock_all_queues();
            FIRD_VK_CHECK(vkDeviceWaitIdle(ctx.device()));
        }
    }
    target.reset();
    if (win) {
        glfwGetWindowSize(win->window, &settings.window_w, &settings.window_h);
        save_settings(settings);
        ImGui_ImplGlfw_Shutdown();
        ImGui_ImplVulkanH_DestroyWindow(ctx.instance(), ctx.device(), &win->wd, nullptr);
        glfwDestroyWindow(win->window);
    }
    if (options.stats)
        std::printf("%s\n", nlohmann::json{{"frame_ms_p50", percentile(frame_ms, 0.5)},
                                           {"frame_ms_p99", percentile(frame_ms, 0.99)},
                                           {"build_ms_p50", percentile(build_ms, 0.5)},
                                           {"build_ms_p99", percentile(build_ms, 0.99)},
                                           {"present_ms_p50", percentile(present_ms, 0.5)},
                                           {"present_ms_p99", percentile(present_ms, 0.99)},
                                           {"frames", frame_ms.size()},
                                           {"first_frame_ms", first_frame_ms},
                                           {"offscreen", offscreen},
                                           // offscreen: the frames drawn into the image
                                           {"frames_drawn", offscreen ? nlohmann::json(frames_drawn)
                                                                      : nlohmann::json(nullptr)},
                                           {"device", ctx.summary().name},
                                           {"separate_work_queue", ctx.separate_work_queue()},
                                           {"rays_traced", rays},
                                           {"evaluations", evaluations},
                                           {"window", window_size},
                                           {"panels", panels},
                                           {"camera", camera},
                                           {"parameters", sliders},
                                           {"follow", followed},
                                           {"job", job},
                                           {"tolerance", tolerance},
                                           {"cad", cad}}
                                .dump(2)
                                .c_str());
    if (ctx.validation_errors() > 0) {
        std::fprintf(stderr, "fird: error: Vulkan validation errors were reported (see above)\n");
        return 1;
    }
    return exit_code;
}

std::vector<std::uint8_t> render_workbench_offscreen(const std::string& device_name,
                                                     bool validation, const std::string& scene,
                                                     std::uint32_t w, std::uint32_t h,
                                                     std::uint64_t* validation_errors) {
    const auto ctx = vk::Context::create({.validation = validation, .device_name = device_name});
    vk::require_fragment_shaders(ctx);
    const ImGuiScope imgui;
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(float(w), float(h));
    io.DeltaTime = 1.0f / 60.0f;
    std::vector<std::uint8_t> rgba;
    {
        ImGuiRenderer renderer(ctx, 1);
        Session session(ctx);
        session.state.wait_for_views = true; // the picture shows the views as they are
        if (!open_scene(session.state, scene)) throw std::runtime_error(session.state.editor.error);
        // One full trace, no preview.
        session.state.editor.preview_rays = session.state.editor.scene->trace.rays;
        // Frames until the trace is shown (bounded: a trace that never ends is an error).
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(10);
        for (int settled = 0; settled < 3;) {
            ImGui::NewFrame();
            Frame f = session.frame();
            build_frame(f);
            ImGui::Render();
            const bool shown = f.snapshot && !f.worker.busy() && !session.state.editor.dirty;
            settled = shown ? settled + 1 : 0;
            if (!shown) std::this_thread::sleep_for(std::chrono::milliseconds(20));
            if (std::chrono::steady_clock::now() > deadline)
                throw std::runtime_error(scene + ": the trace did not finish within 10 minutes");
            for (const std::string& line : session.state.log)
                if (line.rfind("error:", 0) == 0) throw std::runtime_error(line.substr(7));
        }
        rgba = draw_offscreen(ctx, renderer, ImGui::GetDrawData(), w, h, 0);
    }
    if (validation_errors) *validation_errors = ctx.validation_errors();
    return rgba;
}

} // namespace fird::ui
