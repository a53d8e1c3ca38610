// libfird_cad.so's entry point: the table of its exports (export_modules.hpp).
#include "export/export_modules.hpp"
#include "fird_module_stamp.h"

namespace {

constexpr fird::CadExports kTable{.stamp = FIRD_MODULE_STAMP, .cad = &fird::export_cad};

} // namespace

extern "C" __attribute__((visibility("default"))) const fird::CadExports* fird_cad_exports() {
    return &kTable;
}
