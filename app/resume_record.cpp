#include "resume_record.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "io/sha256.hpp"
#include "version.hpp"

namespace fird::app {

namespace {

struct NamedFile {
    const char* what; // how messages name it: "mesh", "target"
    std::string file; // as the scene writes it (part of the scene's text)
    std::string path; // resolved beside the scene file
};

// Every file the scene names (scene_file.cpp resolves these two and no others).
std::vector<NamedFile> named_files(const Scene& scene) {
    std::vector<NamedFile> files;
    if (scene.reflector.family == Family::Mesh)
        files.push_back({"mesh", scene.reflector.mesh.file, scene.reflector.mesh.resolved_path});
    if (scene.target.kind == TargetDesc::Kind::Photometric)
        files.push_back({"target", scene.target.file, scene.target.resolved_path});
    return files;
}

nlohmann::json device_json(const vk::DeviceSummary& d) {
    return {{"name", d.name},
            {"driver_name", d.driver_name},
            {"driver_info", d.driver_info},
            {"driver_version", d.driver_version}};
}

[[noreturn]] void changed(const std::string& dir, const std::string& what,
                          const std::string& detail) {
    throw std::runtime_error(
        fmt::format("--resume {}: {} has changed since the search began{}", dir, what, detail));
}

const nlohmann::json& recorded_part(const std::string& dir, const nlohmann::json& recorded,
                                    const char* key) {
    if (!recorded.is_object() || !recorded.contains(key))
        throw std::runtime_error(fmt::format(
            "--resume {}: options.json does not record the {} the search depends on (written "
            "by an older fird): start the search afresh",
            dir, key));
    return recorded.at(key);
}

} // namespace

nlohmann::json depends_on_record(const Scene& scene, const vk::DeviceSummary& device) {
    nlohmann::json files = nlohmann::json::array();
    for (const NamedFile& f : named_files(scene))
        files.push_back({{"what", f.what},
                         {"file", f.file},
                         {"path", f.path},
                         {"sha256", file_sha256_hex(f.path)}});
    return {{"program", program_version()}, {"files", files}, {"device", device_json(device)}};
}

void check_program_and_files(const std::string& dir, const nlohmann::json& recorded,
                             const Scene& scene) {
    const std::string then = recorded_part(dir, recorded, "program").get<std::string>();
    if (then != program_version())
        changed(dir, "fird", fmt::format(" ({} then, {} now)", then, program_version()));
    const nlohmann::json& files = recorded_part(dir, recorded, "files");
    for (const NamedFile& f : named_files(scene)) {
        const auto was = std::find_if(files.begin(), files.end(), [&](const nlohmann::json& j) {
            return j.at("what") == f.what && j.at("file") == f.file;
        });
        // The scene's text names its files and was checked first; a file it names that the
        // record lacks is a record from another scene.
        if (was == files.end()) changed(dir, fmt::format("{} {}", f.what, f.path), "");
        std::string now;
        try {
            now = file_sha256_hex(f.path);
        } catch (const std::runtime_error&) {
            changed(dir, fmt::format("{} {}", f.what, f.path), " (it cannot be read now)");
        }
        if (now != was->at("sha256").get<std::string>())
            changed(dir, fmt::format("{} {}", f.what, f.path), "");
    }
}

void check_device(const std::string& dir, const nlohmann::json& recorded,
                  const vk::DeviceSummary& device) {
    const nlohmann::json& then = recorded_part(dir, recorded, "device");
    const nlohmann::json now = device_json(device);
    if (then == now) return;
    const auto describe = [](const nlohmann::json& d) {
        return fmt::format("{}, {} {} (driver version {})", d.at("name").get<std::string>(),
                           d.at("driver_name").get<std::string>(),
                           d.at("driver_info").get<std::string>(),
                           d.at("driver_version").get<std::uint32_t>());
    };
    changed(dir, then.at("name") == now.at("name") ? "the device's driver" : "the device",
            fmt::format(" ({} then; {} now)", describe(then), describe(now)));
}

} // namespace fird::app
