// What a search's result depends on besides its settings and the scene's text, recorded
// in options.json ("depends_on") when the search begins, so that --resume refuses to
// continue one whose inputs changed underneath it: the contents of every file the scene
// names (the mesh reflector, the photometric target), the program's version, and the
// device with its driver (the same scene and seed give the same histogram only on the
// same device, DESIGN.md §2).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "model/scene.hpp"
#include "vk/context.hpp"

namespace fird::app {

// {"program": ..., "files": [{"what", "file" (as the scene writes it), "path", "sha256"}],
//  "device": {"name", "driver_name", "driver_info", "driver_version"}}
nlohmann::json depends_on_record(const Scene& scene, const vk::DeviceSummary& device);

// Throws std::runtime_error "--resume DIR: WHAT has changed since the search began (...)"
// at the first difference between `recorded` (options.json's "depends_on") and what holds
// now. The program and the files are checked first (no device needed): check_device after.
void check_program_and_files(const std::string& dir, const nlohmann::json& recorded,
                             const Scene& scene);
void check_device(const std::string& dir, const nlohmann::json& recorded,
                  const vk::DeviceSummary& device);

} // namespace fird::app
