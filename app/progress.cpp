#include "progress.hpp"

#include <chrono>
#include <cstdint>
#include <cstdio>

#include <fmt/format.h>
#include <unistd.h>

namespace fird::app {

namespace {
double now_s() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
} // namespace

ProgressLine::ProgressLine() : live_(isatty(fileno(stderr)) != 0), start_s_(now_s()) {}

ProgressLine::~ProgressLine() {
    finish();
}

void ProgressLine::finish() {
    if (shown_) std::fputs("\n", stderr);
    shown_ = false;
}

double ProgressLine::elapsed_s() const {
    return now_s() - start_s_;
}

void ProgressLine::show(const std::string& text) {
    if (!live_) return;
    std::fprintf(stderr, "\r\033[K%s", text.c_str());
    std::fflush(stderr);
    shown_ = true;
}

std::string clock_time(double s) {
    const auto t = std::uint64_t(s + 0.5);
    return t >= 3600 ? fmt::format("{}:{:02}:{:02}", t / 3600, t / 60 % 60, t % 60)
                     : fmt::format("{}:{:02}", t / 60, t % 60);
}

} // namespace fird::app
