// Ctrl-C and SIGTERM while long work runs: the first one asks the work to stop cleanly
// (through its SearchControl), a second one ends the process at once.
#pragma once

#include "optimize/search_types.hpp"

namespace fird::app {

class InterruptScope {
  public:
    explicit InterruptScope(SearchControl& control);
    ~InterruptScope();
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;
};

} // namespace fird::app
