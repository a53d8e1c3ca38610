// libfird_vtk.so's entry point: the table of its exports (export_modules.hpp).
#include "export/export_modules.hpp"
#include "fird_module_stamp.h"

namespace {

constexpr fird::VtkExports kTable{.stamp = FIRD_MODULE_STAMP,
                                  .scene = &fird::export_scene,
                                  .search_reflectors = &fird::export_search_reflectors};

} // namespace

extern "C" __attribute__((visibility("default"))) const fird::VtkExports* fird_vtk_exports() {
    return &kTable;
}
