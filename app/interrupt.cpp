#include "interrupt.hpp"

#include <atomic>
#include <csignal>
#include <cstring>

#include <unistd.h>

namespace fird::app {

namespace {

// The one piece of process state: a signal handler can reach nothing else. It points at
// the running work's control while an InterruptScope lives.
std::atomic<SearchControl*> g_target{nullptr};

extern "C" void on_interrupt(int) {
    SearchControl* c = g_target.load();
    if (!c) return;
    c->stop.store(true);
    // write(2) and strlen are async-signal-safe; the note outlives the handler's call.
    if (const char* note = c->stop_note.load()) {
        (void)!write(STDERR_FILENO, note, std::strlen(note));
        c->noted.store(true);
    }
}

} // namespace

InterruptScope::InterruptScope(SearchControl& control) {
    g_target.store(&control);
    struct sigaction action {};
    action.sa_handler = on_interrupt;
    action.sa_flags = SA_RESETHAND; // a second signal takes the default action
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

InterruptScope::~InterruptScope() {
    g_target.store(nullptr);
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
}

} // namespace fird::app
