#include "vtk_file.hpp"

#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <vtkDataObject.h>
#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkStructuredGrid.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>
#include <vtkXMLStructuredGridWriter.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "io/atomic_file.hpp"

namespace fird::vtkio {

namespace {

vtkSmartPointer<vtkXMLWriter> writer_for(const std::string& ext) {
    if (ext == ".vts") return vtkSmartPointer<vtkXMLStructuredGridWriter>::New();
    if (ext == ".vtu") return vtkSmartPointer<vtkXMLUnstructuredGridWriter>::New();
    if (ext == ".vtp") return vtkSmartPointer<vtkXMLPolyDataWriter>::New();
    if (ext == ".vti") return vtkSmartPointer<vtkXMLImageDataWriter>::New();
    return nullptr;
}

} // namespace

std::uint64_t write_dataset(const std::string& path, vtkDataObject* data) {
    const std::string ext = std::filesystem::path(path).extension().string();
    const auto writer = writer_for(ext);
    if (!writer) throw std::invalid_argument(fmt::format("{}: not a VTK XML dataset name", path));
    write_atomically(path, [&](const std::string& temporary) {
        writer->SetFileName(temporary.c_str());
        writer->SetInputDataObject(data);
        writer->SetDataModeToAppended();
        writer->EncodeAppendedDataOff(); // raw binary, as ParaView writes
        writer->SetCompressorTypeToZLib();
        if (writer->Write() != 1 || writer->GetErrorCode() != 0)
            throw std::runtime_error(fmt::format("{}: VTK could not write it", path));
    });
    return std::filesystem::file_size(path);
}

std::uint64_t write_collection(const std::string& path,
                               const std::vector<CollectionEntry>& entries) {
    namespace fs = std::filesystem;
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
                      "byte_order=\"LittleEndian\">\n  <Collection>\n";
    for (const CollectionEntry& e : entries) {
        if (!fs::is_regular_file(fs::path(path).parent_path() / e.file))
            throw std::logic_error(
                fmt::format("{}: lists {}, which was not written", path, e.file));
        xml += fmt::format("    <DataSet timestep=\"{}\" part=\"{}\" file=\"{}\"/>\n", e.timestep,
                           e.part, e.file);
    }
    xml += "  </Collection>\n</VTKFile>\n";
    write_text_file(path, xml);
    return fs::file_size(path);
}

} // namespace fird::vtkio
