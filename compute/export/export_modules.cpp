#include "export/export_modules.hpp"

#include "io/program_files.hpp"

namespace fird {

const VtkExports& vtk_exports() {
    return program_module_table<VtkExports>(kVtkModuleFile, kVtkModuleSymbol);
}

const CadExports& cad_exports() {
    return program_module_table<CadExports>(kCadModuleFile, kCadModuleSymbol);
}

} // namespace fird
