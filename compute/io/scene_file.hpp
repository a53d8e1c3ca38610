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

// The scene with every file it names (a mesh, a photometric target or source, a ray file)
// as an absolute path, so that its text reads the same from any folder.
Scene with_absolute_files(Scene scene);

// `text` with its control characters (a newline) made spaces: a scene's name in a comment
// line of a scene file or a script, where a newline would start a line of its own.
std::string one_line(const std::string& text);

// A path that a file names (a scene its mesh, a workbench script its scene), as the
// naming file's reader finds it: an absolute one as it is, a relative one from the naming
// file's folder, wherever the program runs.
std::string resolve_beside(const std::string& naming_file, const std::string& named);

// Validates the whole scene (also called by the loaders); throws SceneError.
void validate_scene(const Scene& scene);

} // namespace fird
