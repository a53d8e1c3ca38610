// Outputs are written whole or not at all: into a temporary file beside the target, then
// renamed over it (rename is atomic within a file system), so an interrupted run never
// leaves a half-written file that looks whole.
#pragma once

#include <functional>
#include <string>

namespace fird {

// Calls `write` with a temporary path beside `path`, then renames it to `path`. On an
// exception the temporary file is removed and the exception passes on.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary)>& write);

// `text` into `path`, atomically; errors name the path.
void write_text_file(const std::string& path, const std::string& text);

// Creates the directory (and parents); errors name it.
void create_output_directory(const std::string& directory);

} // namespace fird
