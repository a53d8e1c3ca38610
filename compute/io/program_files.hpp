// Where the running program is, and the modules that travel with it: shared libraries of
// FIRD's own, each linking one heavy dependency that only some commands use, loaded the
// first time one of those runs (a process that never needs it never pays its start-up).
#pragma once

#include <string>

namespace fird {

// The running program's absolute path (/proc/self/exe).
std::string this_program();

// The address of `symbol` in FIRD's module `file` (e.g. "libfird_pagmo.so"), loaded on the
// first call (and kept loaded). The module is looked for in the lib folder beside the
// program's own folder (the build tree's build/<config>/lib for app/fird and tests/test_*,
// a GPU bundle's lib), then beside the program; never by a path
// fixed at build time, so that a moved copy of the program finds its own modules or none.
// std::runtime_error in one line when it cannot be loaded (naming the module, where it
// was looked for and the loader's reason) or lacks the symbol (naming the file and symbol).
void* program_module_symbol(const std::string& file, const char* symbol);

// Throws std::runtime_error in one line unless `stamp` is this program's: the SHA-256 of the
// engine's headers it was built with (cmake/FirdModuleStamp.cmake), which every module is
// compiled with too. FIRD's own types cross between a module and the program, so only a
// module built from the same headers is accepted.
void check_module_stamp(const std::string& file, const char* stamp);

// The table of functions that FIRD's module `file` returns from its entry point `symbol`
// (an extern "C" function without arguments), the module loaded on the first call. Every
// table begins with `const char* stamp`, checked as above.
template <typename Table>
const Table& program_module_table(const std::string& file, const char* symbol) {
    using Entry = const Table* (*)();
    const Table* table = reinterpret_cast<Entry>(program_module_symbol(file, symbol))();
    check_module_stamp(file, table->stamp);
    return *table;
}

} // namespace fird
