// An option the CAD export cannot honour (--cad-tolerance, --thickness): a usage error
// (exit 2). Its own header, so that the command line includes no OpenCASCADE header.
#pragma once

#include <stdexcept>

namespace fird {

struct CadOptionError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

} // namespace fird
