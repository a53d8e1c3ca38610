// The exports that link VTK and OpenCASCADE, as the program calls them: through FIRD's
// modules libfird_vtk.so (scene_export.hpp: ParaView's files) and libfird_cad.so
// (cad_export.hpp: STEP and STL), each loaded the first time one of its exports runs
// (io/program_files.hpp), so that a command that exports nothing never loads VTK or
// OpenCASCADE: their relocations and static initialization took ~20 and 50-60 ms of every
// process's start on the AMD EPYC of docs/benchmarks.md ("Start-up"). The modules are
// built of export/'s own files only; what they call of the engine (the Evaluator, the
// Surface, the file writers) they find in the program, which exports its fird:: symbols
// for them (cmake/fird_module_exports.list). FIRD's own types cross (Scene, Surface,
// SearchResult, the reports), so a module is accepted only from a build of the same engine
// headers: each table begins with the SHA-256 of those headers it was compiled with
// (cmake/FirdModuleStamp.cmake), which the program compares with its own
// (io/program_files.hpp, as for every module).
#pragma once

#include <string>

#include "export/cad_export.hpp"
#include "export/scene_export.hpp"

namespace fird {

inline constexpr const char* kVtkModuleFile = "libfird_vtk.so";
inline constexpr const char* kVtkModuleSymbol = "fird_vtk_exports";
inline constexpr const char* kCadModuleFile = "libfird_cad.so";
inline constexpr const char* kCadModuleSymbol = "fird_cad_exports";

// libfird_vtk.so's functions: export_scene and export_search_reflectors (scene_export.hpp).
struct VtkExports {
    const char* stamp = nullptr; // FIRD_MODULE_STAMP of the module's build: first, always
    ExportReport (*scene)(const vk::Context& ctx, const Scene& scene, const ExportOptions& options,
                          const std::string& directory) = nullptr;
    ExportReport (*search_reflectors)(const Scene& scene, const SearchResult& result,
                                      const std::string& directory) = nullptr;
};

// libfird_cad.so's: export_cad (cad_export.hpp).
struct CadExports {
    const char* stamp = nullptr;
    CadReport (*cad)(const Surface& surface, const CadOptions& options,
                     const std::string& directory) = nullptr;
};

// Each module's table, the module loaded on the first call (a later call finds it loaded).
// std::runtime_error in one line when the module is missing, cannot be loaded (one of the
// program's symbols it needs missing among them) or was built from other engine headers. A command
// calls these before its device and its first file, so that a broken installation fails before any
// work.
const VtkExports& vtk_exports();
const CadExports& cad_exports();

} // namespace fird
