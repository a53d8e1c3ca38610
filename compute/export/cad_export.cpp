#include "cad_export.hpp"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>

#include "cad_crease.hpp"
#include "cad_curvature.hpp"
#include "cad_step.hpp"
#include "cad_stl.hpp"
#include "cad_surface.hpp"
#include "io/atomic_file.hpp"

namespace fird {

namespace {

// Grid points that put `per` samples in each of a grid's intervals (n points).
int refined(int n, int per) {
    return per * (n - 1) + 1;
}

// What the CAD surface is and how far it strays.
CadReport report_of(const CadSurface& cad) {
    return CadReport{.exact = cad.exact,
                     .max_deviation_mm = cad.max_deviation_mm,
                     .worst_xy_mm = cad.worst_xy_mm,
                     .fit_nx = cad.fit_nx,
                     .fit_ny = cad.fit_ny,
                     .check_nx = cad.check_nx,
                     .check_ny = cad.check_ny};
}

std::string file_in(const std::string& directory, const char* name) {
    return (std::filesystem::path(directory) / name).string();
}

// A reflector clamped to the holder's z range: the unclamped family fitted (or exact) and
// trimmed there, flat beyond; no sheet (the crease would need a bend radius).
CadReport export_creased(const Surface& surface, const Creases& creases, const CadOptions& o,
                         const std::string& directory) {
    if (o.thickness_mm > 0.0)
        throw CadOptionError(fmt::format(
            "--thickness {:g}: the reflector meets the holder's {} in a crease (it is clamped "
            "there), and a sheet needs a bend radius there, which this export does not make; "
            "export the surface alone",
            o.thickness_mm, creases.top ? "top" : "floor"));
    const CadSurface cad = make_cad_surface(surface, o.tolerance_mm, Heights::Unclamped);
    CadReport r = report_of(cad);
    r.creased = true;
    const TopoDS_Shape shell = creased_shell(cad.surface, surface, creases);
    r.edge_tolerance_mm = BRep_Tool::MaxTolerance(shell, TopAbs_EDGE);
    r.stl_chord_mm = o.tolerance_mm;
    create_output_directory(directory);
    write_step(shell, file_in(directory, "reflector.step"));
    r.files.push_back(
        {"reflector.step", std::filesystem::file_size(file_in(directory, "reflector.step"))});
    r.files.push_back(
        {"reflector.stl",
         write_tessellated_stl(shell, o.tolerance_mm, file_in(directory, "reflector.stl"))});
    return r;
}

CadReport export_cad_unguarded(const Surface& surface, const CadOptions& o,
                               const std::string& directory) {
    if (!(o.tolerance_mm > 0.0))
        throw CadOptionError(fmt::format("--cad-tolerance {:g}: must be > 0 mm", o.tolerance_mm));
    if (!(o.thickness_mm >= 0.0))
        throw CadOptionError(fmt::format("--thickness {:g}: must be >= 0 mm (0: the surface alone)",
                                         o.thickness_mm));
    if (!std::holds_alternative<MeshFn>(surface.function()))
        if (const Creases creases = clamp_creases(surface); creases.any())
            return export_creased(surface, creases, o, directory);
    const CadSurface cad = make_cad_surface(surface, o.tolerance_mm);
    CadReport r = report_of(cad);
    // The exact B-spline has few knot intervals: eight samples in each (at least 129 an
    // axis) for the STL and the curvature; a fit's own samples already resolve its detail.
    r.stl_nx = cad.exact ? std::max(129, refined(cad.fit_nx, 8)) : cad.fit_nx;
    r.stl_ny = cad.exact ? std::max(129, refined(cad.fit_ny, 8)) : cad.fit_ny;
    const BackCurvature back =
        smallest_back_radius(cad.surface, refined(r.stl_nx, 2), refined(r.stl_ny, 2));
    r.back_radius_mm = back.smallest_radius_mm;
    r.back_radius_xy_mm = back.where_xy_mm;
    if (o.thickness_mm > 0.0 && o.thickness_mm >= r.back_radius_mm)
        throw CadOptionError(fmt::format(
            "--thickness {:g}: the back face would intersect itself where the surface bends "
            "towards it with a radius of {:.3g} mm at ({:.2f}, {:.2f}) mm; use a thinner sheet",
            o.thickness_mm, back.smallest_radius_mm, back.where_xy_mm.x, back.where_xy_mm.y));
    const TopoDS_Shape shape = reflector_shape(cad.surface, o.thickness_mm);
    const SurfaceGrid grid = sample_surface(cad.surface, r.stl_nx, r.stl_ny);
    r.stl_chord_mm = chord_error_mm(grid, cad.surface);

    create_output_directory(directory);
    const std::string step = file_in(directory, "reflector.step");
    write_step(shape, step);
    r.files.push_back({"reflector.step", std::filesystem::file_size(step)});
    const std::string stl = file_in(directory, "reflector.stl");
    r.files.push_back({"reflector.stl", write_reflector_stl(grid, o.thickness_mm, stl)});
    return r;
}

} // namespace

CadReport export_cad(const Surface& surface, const CadOptions& o, const std::string& directory) {
    // OpenCASCADE throws Standard_Failure, which is no std::exception: one line, not an abort.
    try {
        return export_cad_unguarded(surface, o, directory);
    } catch (const Standard_Failure& e) {
        throw std::runtime_error(
            fmt::format("OpenCASCADE ({}): {}", e.DynamicType()->Name(), e.GetMessageString()));
    }
}

} // namespace fird
