#include "cad_step.hpp"

#include <stdexcept>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepOffsetAPI_MakeThickSolid.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Writer.hxx>
#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fird {

TopoDS_Face height_field_face(const Handle(Geom_BSplineSurface) & surface) {
    // The face's normal is the surface's D1U x D1V, up (+z) for S(u, v) = (u, v, z).
    BRepBuilderAPI_MakeFace face(surface, 1e-7);
    if (!face.IsDone()) throw std::runtime_error("OpenCASCADE could not make the reflector face");
    return face.Face();
}

TopoDS_Shape thickened(const TopoDS_Shape& top, double thickness_mm) {
    // The back face lies at minus the thickness along the faces' (upward) normals.
    BRepOffsetAPI_MakeThickSolid thick;
    thick.MakeThickSolidBySimple(top, -thickness_mm);
    if (!thick.IsDone())
        throw std::runtime_error(fmt::format(
            "--thickness {:g}: OpenCASCADE could not thicken the reflector", thickness_mm));
    TopoDS_Shape solid = thick.Shape();
    // Its faces point out: a positive volume (the offset follows the faces' orientation).
    GProp_GProps mass;
    BRepGProp::VolumeProperties(solid, mass);
    if (mass.Mass() < 0.0) solid.Reverse();
    if (!BRepCheck_Analyzer(solid).IsValid())
        throw std::runtime_error(
            fmt::format("--thickness {:g}: OpenCASCADE made an invalid solid sheet", thickness_mm));
    return solid;
}

TopoDS_Shape reflector_shape(const TopoDS_Shape& face, double thickness_mm) {
    if (thickness_mm <= 0.0) return face;
    return thickened(face, thickness_mm);
}

void write_step(const TopoDS_Shape& shape, const std::string& path) {
    // The writer reports its progress on OpenCASCADE's default messenger (stdout); the
    // command prints its own summary, so its printers go (a process-wide OCCT setting).
    Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
    STEPControl_Writer writer;
    Interface_Static::SetCVal("write.step.unit", "MM");
    Interface_Static::SetCVal("write.step.schema", "AP214IS");
    if (writer.Transfer(shape, STEPControl_AsIs) != IFSelect_RetDone)
        throw std::runtime_error(fmt::format("{}: OpenCASCADE could not translate the reflector "
                                             "to STEP",
                                             path));
    write_atomically(path, [&](const std::string& temporary) {
        if (writer.Write(temporary.c_str()) != IFSelect_RetDone)
            throw std::runtime_error(fmt::format("{}: cannot write", path));
    });
}

} // namespace fird
