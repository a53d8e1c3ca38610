// The program's version: the project's version and the git commit it was built from
// (cmake/FirdVersion.cmake), e.g. "0.1.0 (0491d4f8c9fc)"; the project's version alone
// when built outside a git checkout.
#pragma once

namespace fird::app {

const char* program_version();

} // namespace fird::app
