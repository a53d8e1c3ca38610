#include "context.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <thread>

#include <fmt/format.h>

#include "check.hpp"

namespace fird::vk {

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
// Push descriptors let each compute pass own its bindings without descriptor pools.
constexpr const char* kRequiredDeviceExtensions[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

const char* type_name(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "cpu";
    default:
        return "other";
    }
}

int type_rank(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return 1;
    default:
        return 0;
    }
}

bool has_layer(const char* name) {
    std::uint32_t n = 0;
    FIRD_VK_CHECK(vkEnumerateInstanceLayerProperties(&n, nullptr));
    std::vector<VkLayerProperties> layers(n);
    FIRD_VK_CHECK(vkEnumerateInstanceLayerProperties(&n, layers.data()));
    return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
        return std::strcmp(l.layerName, name) == 0;
    });
}

bool has_instance_extension(const char* name) {
    std::uint32_t n = 0;
    FIRD_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr));
    std::vector<VkExtensionProperties> exts(n);
    FIRD_VK_CHECK(vkEnumerateInstanceExtensionProperties(nullptr, &n, exts.data()));
    return std::any_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

std::vector<std::string> device_extensions(VkPhysicalDevice pd) {
    std::uint32_t n = 0;
    FIRD_VK_CHECK(vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr));
    std::vector<VkExtensionProperties> exts(n);
    FIRD_VK_CHECK(vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data()));
    std::vector<std::string> names;
    for (const auto& e : exts)
        names.emplace_back(e.extensionName);
    return names;
}

std::vector<VkQueueFamilyProperties> queue_families(VkPhysicalDevice pd) {
    std::uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
    return families;
}

// A queue family that does both graphics and compute: the view and the compute
// pipeline share one device and one queue, so no ownership transfers are needed.
std::int64_t universal_queue_family(VkPhysicalDevice pd) {
    const auto families = queue_families(pd);
    for (std::uint32_t i = 0; i < families.size(); ++i) {
        const auto want = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        if ((families[i].queueFlags & want) == want) return i;
    }
    return -1;
}

// The queues to create in that family: two where it has them (the work's own), else one.
std::uint32_t work_queues_for(VkPhysicalDevice pd, std::uint32_t family) {
    return std::min<std::uint32_t>(2, queue_families(pd)[family].queueCount);
}

DeviceSummary summarize(VkPhysicalDevice pd, const std::vector<std::string>& extra_extensions) {
    VkPhysicalDeviceDriverProperties driver{
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
                                      .pNext = &driver};
    vkGetPhysicalDeviceProperties2(pd, &props);
    DeviceSummary s{.name = props.properties.deviceName,
                    .type = type_name(props.properties.deviceType),
                    .driver_name = driver.driverName,
                    .driver_info = driver.driverInfo,
                    .driver_version = props.properties.driverVersion,
                    .api_version = props.properties.apiVersion};
    if (props.properties.apiVersion < VK_API_VERSION_1_3) {
        s.unusable_reason = "Vulkan 1.3 is required";
    } else if (universal_queue_family(pd) < 0) {
        s.unusable_reason = "no queue family with both graphics and compute";
    } else {
        const auto exts = device_extensions(pd);
        std::vector<std::string> wanted(std::begin(kRequiredDeviceExtensions),
                                        std::end(kRequiredDeviceExtensions));
        wanted.insert(wanted.end(), extra_extensions.begin(), extra_extensions.end());
        for (const auto& w : wanted)
            if (std::find(exts.begin(), exts.end(), w) == exts.end()) {
                s.unusable_reason = "missing device extension " + w;
                break;
            }
    }
    if (s.unusable_reason.empty()) {
        // Optional in Vulkan 1.3, and every driver FIRD runs on has it: the scene's
        // parameters are a uniform buffer in the C struct's (scalar) layout (common.glsl).
        VkPhysicalDeviceVulkan12Features f12{
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                           .pNext = &f12};
        vkGetPhysicalDeviceFeatures2(pd, &features);
        if (!f12.scalarBlockLayout) s.unusable_reason = "missing device feature scalarBlockLayout";
    }
    s.usable = s.unusable_reason.empty();
    return s;
}

VkBool32 VKAPI_PTR on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                    VkDebugUtilsMessageTypeFlagsEXT,
                                    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        static_cast<std::atomic<std::uint64_t>*>(user)->fetch_add(1);
        std::fprintf(stderr, "vulkan validation error: %s\n", data->pMessage);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        std::fprintf(stderr, "vulkan validation warning: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

VkInstance create_instance(const ContextOptions& options, bool& validation, bool& debug_utils) {
    validation = options.validation && has_layer(kValidationLayer);
    debug_utils = has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    std::vector<const char*> extensions;
    if (debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    for (const auto& e : options.instance_extensions)
        extensions.push_back(e.c_str());
    std::vector<const char*> layers;
    if (validation) layers.push_back(kValidationLayer);

    const VkApplicationInfo app{.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                                .pApplicationName = "fird",
                                .applicationVersion = VK_MAKE_VERSION(0, 1, 0),
                                .pEngineName = "fird",
                                .engineVersion = VK_MAKE_VERSION(0, 1, 0),
                                .apiVersion = VK_API_VERSION_1_3};
    const VkInstanceCreateInfo info{.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
                                    .pApplicationInfo = &app,
                                    .enabledLayerCount = static_cast<std::uint32_t>(layers.size()),
                                    .ppEnabledLayerNames = layers.data(),
                                    .enabledExtensionCount =
                                        static_cast<std::uint32_t>(extensions.size()),
                                    .ppEnabledExtensionNames = extensions.data()};
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
        throw NoDeviceError("no Vulkan driver found (install mesa-vulkan-drivers for lavapipe)");
    FIRD_VK_CHECK(r);
    return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
    std::uint32_t n = 0;
    FIRD_VK_CHECK(vkEnumeratePhysicalDevices(instance, &n, nullptr));
    std::vector<VkPhysicalDevice> devices(n);
    FIRD_VK_CHECK(vkEnumeratePhysicalDevices(instance, &n, devices.data()));
    return devices;
}

DeviceLimits query_limits(VkPhysicalDevice pd, std::uint32_t queue_family, bool atomic_float_ext) {
    VkPhysicalDeviceSubgroupProperties subgroup{
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceMaintenance3Properties maint3{
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES, .pNext = &subgroup};
    VkPhysicalDeviceProperties2 props{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
                                      .pNext = &maint3};
    vkGetPhysicalDeviceProperties2(pd, &props);
    const auto& l = props.properties.limits;
    DeviceLimits out;
    for (int i = 0; i < 3; ++i) {
        out.max_workgroup_size[i] = l.maxComputeWorkGroupSize[i];
        out.max_workgroup_count[i] = l.maxComputeWorkGroupCount[i];
    }
    out.max_workgroup_invocations = l.maxComputeWorkGroupInvocations;
    out.max_storage_buffer_range = l.maxStorageBufferRange;
    out.max_texel_buffer_elements = l.maxTexelBufferElements;
    out.max_memory_allocation_size = maint3.maxMemoryAllocationSize;
    out.subgroup_size = subgroup.subgroupSize;
    out.max_image_dimension_2d = l.maxImageDimension2D;
    out.timestamp_period_ns = l.timestampPeriod;

    out.timestamps =
        queue_families(pd)[queue_family].timestampValidBits > 0 && l.timestampPeriod > 0.0f;

    if (atomic_float_ext) {
        VkPhysicalDeviceShaderAtomicFloatFeaturesEXT af{
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
        VkPhysicalDeviceFeatures2 f{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                    .pNext = &af};
        vkGetPhysicalDeviceFeatures2(pd, &f);
        out.float32_atomic_add = af.shaderBufferFloat32AtomicAdd == VK_TRUE;
    }
    VkPhysicalDeviceMemoryProperties mem;
    vkGetPhysicalDeviceMemoryProperties(pd, &mem);
    for (std::uint32_t i = 0; i < mem.memoryHeapCount; ++i)
        if (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            out.device_local_heap_bytes =
                std::max<std::uint64_t>(out.device_local_heap_bytes, mem.memoryHeaps[i].size);
    return out;
}

} // namespace

struct Context::State {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;      // frames and their redraws (and all work, if alone)
    VkQueue work_queue = VK_NULL_HANDLE; // submit_and_wait's: a second queue when there is one
    std::uint32_t queue_family = 0;
    DeviceSummary summary;
    DeviceLimits limits;
    std::vector<DeviceSummary> devices;
    bool validation = false;
    bool debug_utils = false;
    std::atomic<std::uint64_t> validation_errors{0};
    std::atomic<std::uint64_t> submissions{0};    // through submit_and_wait, from every thread
    std::atomic<std::uint64_t> staging_copies{0}; // of those, Buffer's staging copies
    VkPhysicalDeviceMemoryProperties memory{};
    // A command pool per thread that submits (pools are not thread-safe), and one lock
    // for the queue: the compute worker and the window's frames submit side by side.
    // Each thread's own pool, command buffer and fence, reused by every submission from
    // that thread (issue 24: none is created per pass). `busy` marks one being recorded or
    // waited on: a submission made from inside another's recording gets buffers of its own.
    struct ThreadSubmitter {
        Owned<VkCommandPool> pool;
        VkCommandBuffer command_buffer = VK_NULL_HANDLE; // freed with the pool
        Owned<VkFence> fence;
        bool busy = false;
    };
    std::mutex pools_mutex;
    std::map<std::thread::id, ThreadSubmitter> command_pools;
    std::mutex queue_mutex;
    std::mutex work_queue_mutex; // unused when the work shares the frames' queue
    std::mutex& work_mutex() { return work_queue == queue ? queue_mutex : work_queue_mutex; }
    std::uint64_t max_device_memory = 0;
    std::uint64_t max_batch_rays = 0;
    bool yield_between_passes = false;
    std::atomic<std::uint64_t> device_memory{0};
    // Every buffer's and image's memory (freed before the device).
    std::unique_ptr<MemoryBlocks> memory_blocks;
    PFN_vkSetDebugUtilsObjectNameEXT set_object_name = nullptr;

    ThreadSubmitter& submitter_for_this_thread(const Context& ctx);
    void set_name(VkObjectType type, std::uint64_t handle, std::string_view text) const;
    // Records, submits on the shared queue and waits (bounded) with t's buffer and fence.
    void submit_with(ThreadSubmitter& t, const std::function<void(VkCommandBuffer)>& record);
    void begin_recording(ThreadSubmitter& t);
    void submit_and_wait_for(ThreadSubmitter& t); // ends t's buffer, submits, waits

    ~State() {
        command_pools.clear();
        memory_blocks.reset();
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (destroy_messenger) destroy_messenger(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
};

Context::Context(std::unique_ptr<State> state) : state_(std::move(state)) {}
Context::~Context() = default;
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;

Context Context::create(const ContextOptions& options) {
    auto s = std::make_unique<State>();
    s->instance = create_instance(options, s->validation, s->debug_utils);

    if (s->debug_utils) {
        s->set_object_name = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
            vkGetInstanceProcAddr(s->instance, "vkSetDebugUtilsObjectNameEXT"));
        if (s->validation) {
            auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(s->instance, "vkCreateDebugUtilsMessengerEXT"));
            const VkDebugUtilsMessengerCreateInfoEXT info{
                .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
                .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
                .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
                .pfnUserCallback = on_debug_message,
                .pUserData = &s->validation_errors};
            FIRD_VK_CHECK(create_messenger(s->instance, &info, nullptr, &s->messenger));
        }
    }

    const auto devices = physical_devices(s->instance);
    if (devices.empty())
        throw NoDeviceError("no Vulkan device found (install mesa-vulkan-drivers for lavapipe)");
    int best = -1;
    int best_rank = -1;
    const std::string wanted = lower(options.device_name);
    for (std::size_t i = 0; i < devices.size(); ++i) {
        s->devices.push_back(summarize(devices[i], options.device_extensions));
        const auto& d = s->devices.back();
        if (!wanted.empty()) {
            if (lower(d.name).find(wanted) == std::string::npos) continue;
            if (!d.usable)
                throw NoDeviceError(
                    fmt::format("device '{}' cannot be used: {}", d.name, d.unusable_reason));
            best = static_cast<int>(i);
            break;
        }
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devices[i], &p);
        if (d.usable && type_rank(p.deviceType) > best_rank) {
            best = static_cast<int>(i);
            best_rank = type_rank(p.deviceType);
        }
    }
    if (best >= 0 && wanted.empty() && options.local_rank) {
        std::vector<std::size_t> alike; // the usable devices of the best kind, in order
        for (std::size_t i = 0; i < devices.size(); ++i) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devices[i], &p);
            if (s->devices[i].usable && type_rank(p.deviceType) == best_rank) alike.push_back(i);
        }
        best = static_cast<int>(alike[*options.local_rank % alike.size()]);
    }
    if (best < 0) {
        std::string names;
        for (const auto& d : s->devices)
            names += fmt::format("{}'{}'{}", names.empty() ? "" : ", ", d.name,
                                 d.usable ? "" : " (" + d.unusable_reason + ")");
        if (!wanted.empty())
            throw NoDeviceError(fmt::format("no Vulkan device matches --device '{}'; found {}",
                                            options.device_name, names));
        throw NoDeviceError(fmt::format("no usable Vulkan device; found {}", names));
    }
    s->physical = devices[static_cast<std::size_t>(best)];
    s->summary = s->devices[static_cast<std::size_t>(best)];
    s->queue_family = static_cast<std::uint32_t>(universal_queue_family(s->physical));
    vkGetPhysicalDeviceMemoryProperties(s->physical, &s->memory);

    const auto available = device_extensions(s->physical);
    const auto has = [&](const char* e) {
        return std::find(available.begin(), available.end(), e) != available.end();
    };
    std::vector<const char*> extensions(std::begin(kRequiredDeviceExtensions),
                                        std::end(kRequiredDeviceExtensions));
    for (const auto& e : options.device_extensions)
        extensions.push_back(e.c_str());
    const bool atomic_float = has(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    s->limits = query_limits(s->physical, s->queue_family, atomic_float);

    VkPhysicalDeviceVulkan13Features f13{.sType =
                                             VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
                                         .synchronization2 = VK_TRUE,
                                         .dynamicRendering = VK_TRUE,
                                         // glslang emits LocalSizeId for SPIR-V 1.6; maintenance4
                                         // (required of every 1.3 device) makes that valid.
                                         .maintenance4 = VK_TRUE};
    VkPhysicalDeviceVulkan12Features f12{.sType =
                                             VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                         .pNext = &f13,
                                         .scalarBlockLayout = VK_TRUE,
                                         .hostQueryReset = VK_TRUE,
                                         .timelineSemaphore = VK_TRUE};
    VkPhysicalDeviceFeatures2 features{.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                       .pNext = &f12};
    // Two queues of the one universal family when it has them (discrete GPUs have 8-16):
    // the worker's compute on the second, so that a window's frames on the first never
    // queue behind it (issue 24 item 4). One family: resources need no ownership
    // transfers, and every hand-over between the queues is a fence the host waited on.
    const std::uint32_t queue_count = work_queues_for(s->physical, s->queue_family);
    const float priorities[2] = {1.0f, 1.0f};
    const VkDeviceQueueCreateInfo queue_info{.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                             .queueFamilyIndex = s->queue_family,
                                             .queueCount = queue_count,
                                             .pQueuePriorities = priorities};
    const VkDeviceCreateInfo device_info{.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
                                         .pNext = &features,
                                         .queueCreateInfoCount = 1,
                                         .pQueueCreateInfos = &queue_info,
                                         .enabledExtensionCount =
                                             static_cast<std::uint32_t>(extensions.size()),
                                         .ppEnabledExtensionNames = extensions.data()};
    FIRD_VK_CHECK(vkCreateDevice(s->physical, &device_info, nullptr, &s->device));
    vkGetDeviceQueue(s->device, s->queue_family, 0, &s->queue);
    vkGetDeviceQueue(s->device, s->queue_family, queue_count - 1, &s->work_queue);

    const State* named = s.get(); // the state outlives its blocks
    s->memory_blocks = std::make_unique<MemoryBlocks>(
        s->device, s->memory, s->limits.max_memory_allocation_size,
        MemoryBlocksOptions{.advise_huge_pages = s->summary.type == "cpu",
                            .name_memory = [named](VkDeviceMemory m, std::string_view text) {
                                named->set_name(VK_OBJECT_TYPE_DEVICE_MEMORY,
                                                reinterpret_cast<std::uint64_t>(m), text);
                            }});
    s->max_device_memory = options.max_device_memory_bytes;
    s->max_batch_rays = options.max_batch_rays;
    s->yield_between_passes = options.yield_between_passes;
    Context ctx(std::move(s));
    ctx.name(ctx.state_->queue, VK_OBJECT_TYPE_QUEUE, "fird.queue");
    if (ctx.separate_work_queue())
        ctx.name(ctx.state_->work_queue, VK_OBJECT_TYPE_QUEUE, "fird.queue.work");
    return ctx;
}

VkInstance Context::instance() const {
    return state_->instance;
}
VkPhysicalDevice Context::physical_device() const {
    return state_->physical;
}
VkDevice Context::device() const {
    return state_->device;
}
VkQueue Context::queue() const {
    return state_->queue;
}
std::uint32_t Context::queue_family() const {
    return state_->queue_family;
}
const DeviceSummary& Context::summary() const {
    return state_->summary;
}
const DeviceLimits& Context::limits() const {
    return state_->limits;
}
const std::vector<DeviceSummary>& Context::all_devices() const {
    return state_->devices;
}
bool Context::validation_enabled() const {
    return state_->validation;
}
std::uint64_t Context::validation_errors() const {
    return state_->validation_errors.load();
}

std::uint64_t Context::staging_copies() const {
    return state_->staging_copies.load();
}

void Context::count_staging_copy() const {
    ++state_->staging_copies;
}

std::uint64_t Context::submissions() const {
    return state_->submissions.load();
}

void Context::set_name(VkObjectType type, std::uint64_t handle, std::string_view text) const {
    state_->set_name(type, handle, text);
}

void Context::State::set_name(VkObjectType type, std::uint64_t handle,
                              std::string_view text) const {
    if (!set_object_name || handle == 0) return;
    const std::string name(text);
    const VkDebugUtilsObjectNameInfoEXT info{.sType =
                                                 VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
                                             .objectType = type,
                                             .objectHandle = handle,
                                             .pObjectName = name.c_str()};
    FIRD_VK_CHECK(set_object_name(device, &info));
}

Context::State::ThreadSubmitter& Context::State::submitter_for_this_thread(const Context& ctx) {
    const std::lock_guard lock(pools_mutex);
    const std::size_t index = command_pools.size();
    ThreadSubmitter& t = command_pools[std::this_thread::get_id()];
    if (!t.pool) {
        const VkCommandPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                           .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT |
                                                    VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                           .queueFamilyIndex = queue_family};
        VkCommandPool p = VK_NULL_HANDLE;
        FIRD_VK_CHECK(vkCreateCommandPool(device, &info, nullptr, &p));
        t.pool = Owned<VkCommandPool>(device, p);
        ctx.name(p, VK_OBJECT_TYPE_COMMAND_POOL, fmt::format("fird.command_pool.{}", index));
        const VkCommandBufferAllocateInfo alloc{.sType =
                                                    VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                                .commandPool = p,
                                                .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                                .commandBufferCount = 1};
        FIRD_VK_CHECK(vkAllocateCommandBuffers(device, &alloc, &t.command_buffer));
        ctx.name(t.command_buffer, VK_OBJECT_TYPE_COMMAND_BUFFER,
                 fmt::format("fird.command_buffer.{}", index));
        const VkFenceCreateInfo fence_info{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f = VK_NULL_HANDLE;
        FIRD_VK_CHECK(vkCreateFence(device, &fence_info, nullptr, &f));
        t.fence = Owned<VkFence>(device, f);
        ctx.name(f, VK_OBJECT_TYPE_FENCE, fmt::format("fird.submit_fence.{}", index));
    }
    return t;
}

MemoryCharge::~MemoryCharge() {
    if (ctx_) ctx_->release_memory(bytes_);
}

MemoryCharge& MemoryCharge::operator=(MemoryCharge&& o) noexcept {
    if (this != &o) {
        if (ctx_) ctx_->release_memory(bytes_);
        ctx_ = std::exchange(o.ctx_, nullptr);
        bytes_ = std::exchange(o.bytes_, 0);
    }
    return *this;
}

void Context::release_memory(std::uint64_t bytes) const {
    state_->device_memory -= bytes;
}

MemoryAllocationCounts Context::memory_allocations() const {
    return state_->memory_blocks->counts();
}

std::uint64_t Context::device_memory_budget() const {
    return state_->max_device_memory;
}

std::uint64_t Context::device_memory_in_use() const {
    return state_->device_memory.load();
}

Context::Memory Context::allocate_memory(const VkMemoryRequirements& req, std::uint32_t type,
                                         std::string_view name, bool dedicated) const {
    const std::uint64_t bytes = req.size;
    const std::uint64_t before = state_->device_memory.fetch_add(bytes);
    Memory out{.charge = MemoryCharge(this, bytes)};
    const auto out_of_memory = [&](const std::string& whose, VkResult r) {
        return VulkanError(
            fmt::format("out of device memory ({}): {} needs {} MB with {} MB in use; lower the "
                        "rays (--rays), the height field or the far field, or raise "
                        "--max-device-memory",
                        whose, name, (bytes + (1 << 20) - 1) >> 20, before >> 20),
            r);
    };
    if (state_->max_device_memory && before + bytes > state_->max_device_memory)
        throw out_of_memory(fmt::format("the limit of {} MB", state_->max_device_memory >> 20),
                            VK_ERROR_OUT_OF_DEVICE_MEMORY);
    try {
        out.allocation = state_->memory_blocks->allocate(req, type, dedicated, name);
    } catch (const VulkanError& e) {
        if (e.result() == VK_ERROR_OUT_OF_DEVICE_MEMORY ||
            e.result() == VK_ERROR_OUT_OF_HOST_MEMORY)
            throw out_of_memory("the device's", e.result());
        throw;
    }
    return out;
}

std::uint64_t Context::max_batch_rays() const {
    return state_->max_batch_rays;
}

std::unique_lock<std::mutex> Context::lock_queue() const {
    return std::unique_lock(state_->queue_mutex);
}

QueueLocks Context::lock_all_queues() const {
    QueueLocks locks{std::unique_lock(state_->queue_mutex), {}};
    if (separate_work_queue()) locks.work = std::unique_lock(state_->work_queue_mutex);
    return locks;
}

bool Context::separate_work_queue() const {
    return state_->work_queue != state_->queue;
}

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
    State::ThreadSubmitter& t = state_->submitter_for_this_thread(*this);
    if (t.busy) { // a submission from inside another's recording: buffers of its own
        // (An upload through a staging buffer while a frame records, say: on a device whose
        // working memory is not host-visible. begin_recording resets the buffer, which
        // the pool must allow.)
        State::ThreadSubmitter nested;
        const VkCommandPoolCreateInfo info{.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                           .flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT |
                                                    VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                           .queueFamilyIndex = state_->queue_family};
        VkCommandPool p = VK_NULL_HANDLE;
        FIRD_VK_CHECK(vkCreateCommandPool(state_->device, &info, nullptr, &p));
        nested.pool = Owned<VkCommandPool>(state_->device, p);
        const VkCommandBufferAllocateInfo alloc{.sType =
                                                    VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                                .commandPool = p,
                                                .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                                .commandBufferCount = 1};
        FIRD_VK_CHECK(vkAllocateCommandBuffers(state_->device, &alloc, &nested.command_buffer));
        const VkFenceCreateInfo fence_info{.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f = VK_NULL_HANDLE;
        FIRD_VK_CHECK(vkCreateFence(state_->device, &fence_info, nullptr, &f));
        nested.fence = Owned<VkFence>(state_->device, f);
        state_->submit_with(nested, record);
        return;
    }
    t.busy = true;
    struct Release {
        bool& busy;
        ~Release() { busy = false; }
    } release{t.busy};
    state_->submit_with(t, record);
}

void Context::State::submit_with(ThreadSubmitter& t,
                                 const std::function<void(VkCommandBuffer)>& record) {
    begin_recording(t);
    record(t.command_buffer);
    submit_and_wait_for(t);
}

void Context::State::begin_recording(ThreadSubmitter& t) {
    // The buffer and fence are idle here: the last submission from this thread was waited
    // on (or never submitted: recording threw), so both can be reset.
    const VkFence fence = t.fence.get();
    FIRD_VK_CHECK(vkResetCommandBuffer(t.command_buffer, 0));
    FIRD_VK_CHECK(vkResetFences(device, 1, &fence));
    const VkCommandBufferBeginInfo begin{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                         .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    FIRD_VK_CHECK(vkBeginCommandBuffer(t.command_buffer, &begin));
}

void Context::State::submit_and_wait_for(ThreadSubmitter& t) {
    const VkFence fence = t.fence.get();
    FIRD_VK_CHECK(vkEndCommandBuffer(t.command_buffer));
    const VkCommandBufferSubmitInfo cb_info{.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO,
                                            .commandBuffer = t.command_buffer};
    const VkSubmitInfo2 submit{.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2,
                               .commandBufferInfoCount = 1,
                               .pCommandBufferInfos = &cb_info};
    {
        const std::lock_guard lock(work_mutex());
        FIRD_VK_CHECK(vkQueueSubmit2(work_queue, 1, &submit, fence));
    }
    ++submissions;
    // Bounded wait: a submission that runs this long has hung the device (the context is
    // then unusable: the error ends the command).
    constexpr std::uint64_t kSubmitTimeoutNs = 600ull * 1000 * 1000 * 1000;
    const VkResult waited = vkWaitForFences(device, 1, &fence, VK_TRUE, kSubmitTimeoutNs);
    if (waited == VK_TIMEOUT)
        throw VulkanError("vkWaitForFences: the device did not finish within 600 s", VK_TIMEOUT);
    FIRD_VK_CHECK(waited);
}

void Context::yield_queue(VkCommandBuffer cb) const {
    // On a queue of its own the work delays no frame: nothing to yield.
    if (!state_->yield_between_passes || separate_work_queue()) return;
    State::ThreadSubmitter& t = state_->submitter_for_this_thread(*this);
    if (!t.busy || t.command_buffer != cb) return; // not this thread's recording: go on
    state_->submit_and_wait_for(t);
    state_->begin_recording(t); // the same buffer: the caller's handle stays valid
}

std::uint32_t Context::find_memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags required,
                                        VkMemoryPropertyFlags preferred) const {
    const auto& m = state_->memory;
    for (const VkMemoryPropertyFlags want : {required | preferred, required})
        for (std::uint32_t i = 0; i < m.memoryTypeCount; ++i)
            if ((type_bits & (1u << i)) && (m.memoryTypes[i].propertyFlags & want) == want)
                return i;
    throw VulkanError("vkAllocateMemory: no memory type with the required properties",
                      VK_ERROR_OUT_OF_DEVICE_MEMORY);
}

std::vector<DeviceSummary> enumerate_devices() {
    bool validation = false;
    bool debug_utils = false;
    VkInstance instance = create_instance({}, validation, debug_utils);
    std::vector<DeviceSummary> out;
    try {
        for (auto pd : physical_devices(instance))
            out.push_back(summarize(pd, {}));
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return out;
}

} // namespace fird::vk
