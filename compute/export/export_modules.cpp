#include "export/export_modules.hpp"

#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "fird_module_stamp.h"
#include "io/program_files.hpp"

namespace fird {

namespace {

template <typename Table> const Table& module_table(const char* file, const char* symbol) {
    using Entry = const Table* (*)();
    const Table* table = reinterpret_cast<Entry>(program_module_symbol(file, symbol))();
    if (!table->stamp || std::strcmp(table->stamp, FIRD_MODULE_STAMP) != 0)
        throw std::runtime_error(fmt::format("FIRD's module {} is from another build (engine "
                                             "headers {:.12}, this program's {:.12})",
                                             file, table->stamp ? table->stamp : "unknown",
                                             FIRD_MODULE_STAMP));
    return *table;
}

} // namespace

const VtkExports& vtk_exports() {
    return module_table<VtkExports>(kVtkModuleFile, kVtkModuleSymbol);
}

const CadExports& cad_exports() {
    return module_table<CadExports>(kCadModuleFile, kCadModuleSymbol);
}

} // namespace fird
