// Runs the `fird` binary for the CLI tests: validation layers on (a validation error
// fails the command), stdout and stderr together.
#pragma once

#include <array>
#include <cstdio>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace fird::test {

struct Result {
    int code; // the exit code, or 128 + the signal that ended it
    std::string out;
};

// A shell line as it is (a job's scripts, a background search), stdout and stderr together.
inline Result run_shell(const std::string& line) {
    FILE* pipe = popen((line + " 2>&1").c_str(), "r");
    if (!pipe) return {-1, ""};
    std::string out;
    std::array<char, 4096> buf{};
    while (std::fgets(buf.data(), int(buf.size()), pipe))
        out += buf.data();
    const int status = pclose(pipe);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status), out};
}

// `prefix` goes before the binary on the shell line: variables (VK_DRIVER_FILES=...) or a
// command such as `timeout 120`.
inline Result run_fird(const std::string& prefix, const std::string& args) {
    return run_shell(prefix + " " + std::string(FIRD_BINARY) + " --validation " + args);
}

// A search's history.csv (in its --out folder) as rows less their last column (a row's wall
// time, ms): what two runs of the same search must share.
inline std::vector<std::string> history_rows(const std::string& dir) {
    std::ifstream in(dir + "/history.csv");
    std::vector<std::string> rows;
    for (std::string line; std::getline(in, line);)
        rows.push_back(line.substr(0, line.rfind(',')));
    return rows;
}

} // namespace fird::test
