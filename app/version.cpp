#include "version.hpp"

#include "fird_version.h" // generated at build time

namespace fird::app {

const char* program_version() {
    return FIRD_VERSION;
}

} // namespace fird::app
