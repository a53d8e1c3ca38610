#include "device_report.hpp"

#include <fmt/format.h>

namespace fird {

namespace {
std::string version_text(std::uint32_t v) {
    return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
                       VK_API_VERSION_PATCH(v));
}
} // namespace

nlohmann::json device_report(const vk::Context& ctx) {
    nlohmann::json devices = nlohmann::json::array();
    for (const auto& d : ctx.all_devices())
        devices.push_back({{"name", d.name},
                           {"type", d.type},
                           {"driver", d.driver_name},
                           {"api_version", version_text(d.api_version)},
                           {"usable", d.usable},
                           {"unusable_reason", d.unusable_reason}});
    const auto& s = ctx.summary();
    const auto& l = ctx.limits();
    return {{"devices", devices},
            {"chosen",
             {{"name", s.name},
              {"type", s.type},
              {"driver", s.driver_name},
              {"driver_info", s.driver_info},
              {"api_version", version_text(s.api_version)}}},
            {"validation", ctx.validation_enabled()},
            // Whether compute has a queue of its own (the workbench's frames do not wait
            // behind it) or shares the one queue.
            {"work_queue", ctx.separate_work_queue() ? "own" : "shared"},
            {"limits",
             {{"max_compute_workgroup_size",
               {l.max_workgroup_size[0], l.max_workgroup_size[1], l.max_workgroup_size[2]}},
              {"max_compute_workgroup_invocations", l.max_workgroup_invocations},
              {"max_compute_workgroup_count",
               {l.max_workgroup_count[0], l.max_workgroup_count[1], l.max_workgroup_count[2]}},
              {"max_storage_buffer_range", l.max_storage_buffer_range},
              {"max_memory_allocation_size", l.max_memory_allocation_size},
              {"device_local_heap_bytes", l.device_local_heap_bytes},
              {"max_image_dimension_2d", l.max_image_dimension_2d},
              {"subgroup_size", l.subgroup_size},
              {"float32_atomic_add", l.float32_atomic_add},
              {"timestamps", l.timestamps},
              {"timestamp_period_ns", l.timestamp_period_ns}}}};
}

std::string device_report_text(const nlohmann::json& r) {
    std::string out = "devices:\n";
    for (const auto& d : r["devices"]) {
        out += fmt::format(
            "  - {} ({}, {}, Vulkan {}){}\n", d["name"].get<std::string>(),
            d["type"].get<std::string>(), d["driver"].get<std::string>(),
            d["api_version"].get<std::string>(),
            d["usable"].get<bool>() ? "" : " unusable: " + d["unusable_reason"].get<std::string>());
    }
    const auto& c = r["chosen"];
    const auto& l = r["limits"];
    out += fmt::format("chosen: {} ({})\n", c["name"].get<std::string>(),
                       c["driver_info"].get<std::string>());
    out += fmt::format("validation layers: {}\n", r["validation"].get<bool>() ? "on" : "off");
    out += fmt::format("compute queue: {}\n", r["work_queue"].get<std::string>() == "own"
                                                  ? "its own (frames do not wait behind it)"
                                                  : "shared with the frames");
    out += fmt::format("max compute workgroup size: {} x {} x {} ({} invocations)\n",
                       l["max_compute_workgroup_size"][0].get<unsigned>(),
                       l["max_compute_workgroup_size"][1].get<unsigned>(),
                       l["max_compute_workgroup_size"][2].get<unsigned>(),
                       l["max_compute_workgroup_invocations"].get<unsigned>());
    out += fmt::format("max compute workgroup count: {} x {} x {}\n",
                       l["max_compute_workgroup_count"][0].get<unsigned>(),
                       l["max_compute_workgroup_count"][1].get<unsigned>(),
                       l["max_compute_workgroup_count"][2].get<unsigned>());
    out += fmt::format("max storage buffer range: {} bytes\n",
                       l["max_storage_buffer_range"].get<std::uint64_t>());
    out += fmt::format("subgroup size: {}\n", l["subgroup_size"].get<unsigned>());
    out += fmt::format("32-bit float atomic add: {}\n",
                       l["float32_atomic_add"].get<bool>() ? "yes" : "no");
    out +=
        fmt::format("timestamps: {} (period {} ns)\n", l["timestamps"].get<bool>() ? "yes" : "no",
                    l["timestamp_period_ns"].get<float>());
    return out;
}

} // namespace fird
