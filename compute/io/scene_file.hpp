// Scene files (TOML, DESIGN.md §5): strict reading and writing back.
#pragma once

#include <stdexcept>
#include <string>

#include "model/scene.hpp"

namespace fird {

// "file:line: [table] key: what is wrong" — one line, for the `fird` command to print.
class SceneError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Reads and validates a scene; throws SceneError naming the file, key and line.
Scene load_scene(const std::string& path);
// Parses scene text (`path` is used for messages and to resolve relative file names).
Scene parse_scene(const std::string& text, const std::string& path);
// Writes the scene as TOML that parse_scene reads back to an equal Scene.
std::string scene_to_toml(const Scene& scene);

// Validates the whole scene (also called by the loaders); throws SceneError.
void validate_scene(const Scene& scene);

} // namespace fird
