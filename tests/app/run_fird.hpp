// Runs the `fird` binary for the CLI tests: validation layers on (a validation error
// fails the command), stdout and stderr together.
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace fird::test {

struct Result {
    int code; // the exit code, or 128 + the signal that ended it
    std::string out;
};

// `prefix` goes before the binary on the shell line: variables (VK_DRIVER_FILES=...) or a
// command such as `timeout 120`.
inline Result run_fird(const std::string& prefix, const std::string& args) {
    const std::string cmd =
        prefix + " " + std::string(FIRD_BINARY) + " --validation " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) return {-1, ""};
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe))
        out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

} // namespace fird::test
