// The ray files of the ray file tests, written by tests/io/write_ray_files.py (an
// independent writer: the standard library of Python alone, no FIRD code) into a fresh
// folder per test process, with its manifest of what it wrote where.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace fird::test {

struct RayFiles {
    std::string dir;
    nlohmann::json manifest;
    std::string operator()(const std::string& name) const { return dir + "/" + name; }
    ~RayFiles() { // the folder goes with the process (about 7 MB)
        std::error_code ignored;
        if (!dir.empty()) std::filesystem::remove_all(dir, ignored);
    }
};

inline const RayFiles& ray_files() {
    static const RayFiles files = [] {
        char folder[] = "/tmp/fird_ray_files_XXXXXX";
        if (!mkdtemp(folder)) throw std::runtime_error("cannot make a folder for the ray files");
        const std::string command = std::string("/usr/bin/python3 ") + FIRD_SOURCE_DIR +
                                    "/tests/io/write_ray_files.py " + folder;
        if (std::system(command.c_str()) != 0)
            throw std::runtime_error("the ray file writer failed: " + command);
        RayFiles f{folder, {}};
        std::ifstream in(f("manifest.json"));
        f.manifest = nlohmann::json::parse(in);
        return f;
    }();
    return files;
}

} // namespace fird::test
