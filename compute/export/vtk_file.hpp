// Writing VTK XML datasets: zlib-compressed binary (ParaView's default), to a temporary
// name renamed into place, and ParaView collections (.pvd) that list them.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

class vtkDataObject;

namespace fird::vtkio {

// Writes `data` with the XML writer its type needs (.vts, .vtu, .vtp, .vti by the
// extension of `path`); returns the file's size in bytes. Errors name the path.
std::uint64_t write_dataset(const std::string& path, vtkDataObject* data);

struct CollectionEntry {
    std::string file; // relative to the collection
    double timestep = 0.0;
    int part = 0;
};

// A .pvd collection of existing files (each entry must exist beside it).
std::uint64_t write_collection(const std::string& path,
                               const std::vector<CollectionEntry>& entries);

} // namespace fird::vtkio
