#include "cad_export.hpp"

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <span>

#include <fmt/format.h>

#include <BRep_Tool.hxx>
#include <Standard_Failure.hxx>

#include "cad_bend.hpp"
#include "cad_crease.hpp"
#include "cad_curvature.hpp"
#include "cad_revolution.hpp"
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

// The samples an axis of a height-field CAD surface's STL (the curvature on twice as many):
// the exact B-spline has few knot intervals, eight samples in each (at least 129); a fit's
// own samples (`fit_n`, that axis's) already resolve its detail.
int sheet_samples(const CadSurface& cad, int fit_n) {
    return cad.exact ? std::max(129, refined(fit_n, 8)) : fit_n;
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

// The bend radius a sheet's creases (and a profile's kink) get: the option's, else twice
// the thickness (the back face's bends then have the thickness for their radius). Where a
// crease bends towards the back (the family rising into the holder's top, a profile rising
// into its flat), the back face bends with the radius less the thickness: it must exceed
// the thickness.
double bend_radius(const CadOptions& o, bool bends_back) {
    const double radius = o.bend_radius_mm > 0.0 ? o.bend_radius_mm : 2.0 * o.thickness_mm;
    if (bends_back && radius <= o.thickness_mm)
        throw CadOptionError(fmt::format(
            "--bend-radius {:g}: must exceed --thickness {:g}, for the reflector bends towards "
            "its back at a crease (its back face bends with the radius less the thickness)",
            radius, o.thickness_mm));
    return radius;
}

// The smallest radius bending towards the back over the surfaces' points within the holder
// (cad_curvature), on an nu x nv grid of each one's parameters, into the report.
void measure_back_radius(CadReport& r, std::span<const Handle(Geom_BSplineSurface)> surfaces,
                         const Holder& holder, int nu, int nv) {
    r.back_radius_mm = std::numeric_limits<double>::infinity();
    for (const Handle(Geom_BSplineSurface) & s : surfaces) {
        const BackCurvature back = smallest_back_radius(s, holder, nu, nv);
        if (back.smallest_radius_mm < r.back_radius_mm) {
            r.back_radius_mm = back.smallest_radius_mm;
            r.back_radius_xy_mm = back.where_xy_mm;
        }
    }
}

// Refuses a sheet thicker than the smallest radius bending towards its back.
void refuse_folding_sheet(const CadOptions& o, const CadReport& r) {
    if (o.thickness_mm > 0.0 && o.thickness_mm >= r.back_radius_mm)
        throw CadOptionError(fmt::format(
            "--thickness {:g}: the back face would intersect itself where the surface bends "
            "towards it with a radius of {:.3g} mm at ({:.2f}, {:.2f}) mm; use a thinner sheet",
            o.thickness_mm, r.back_radius_mm, r.back_radius_xy_mm.x, r.back_radius_xy_mm.y));
}

// A shell of faces meeting in creases as the surface, or as a sheet with the creases bent
// (cad_bend); its STL is OpenCASCADE's tessellation (no grid follows a crease).
CadReport write_creased_part(const TopoDS_Shape& shell, CadReport r, const Surface& surface,
                             bool bends_back, const CadOptions& o, const std::string& directory) {
    r.stl_chord_mm = o.tolerance_mm;
    TopoDS_Shape part = shell;
    if (o.thickness_mm > 0.0) {
        refuse_folding_sheet(o, r); // the family's own bends, before the creases'
        Bend bend;
        part = bent_sheet(shell, surface, bend_radius(o, bends_back), o.thickness_mm, bend);
        r.bend = bend;
    }
    // Meshed before anything is written, so that a failure leaves no STEP file alone.
    const std::vector<StlTriangle> triangles = tessellate(part, o.tolerance_mm);
    create_output_directory(directory);
    write_step(part, file_in(directory, "reflector.step"));
    r.files.push_back(
        {"reflector.step", std::filesystem::file_size(file_in(directory, "reflector.step"))});
    r.files.push_back(
        {"reflector.stl",
         write_stl(triangles,
                   o.thickness_mm > 0.0
                       ? fmt::format("fird reflector, sheet {:g} mm, mm", o.thickness_mm)
                       : std::string("fird reflector surface, mm"),
                   file_in(directory, "reflector.stl"))});
    return r;
}

// A reflector clamped to the holder's z range: the unclamped family's faces (fitted or
// exact) trimmed there, flat beyond (cad_crease).
CadReport export_creased(const TopoDS_Shape& unclamped, CadReport r, const Surface& surface,
                         const Creases& creases, bool kink_bends_back, const CadOptions& o,
                         const std::string& directory) {
    const double radius =
        o.thickness_mm > 0.0 ? bend_radius(o, creases.top || kink_bends_back) : 0.0;
    r.creased = true;
    TopoDS_Shape shell = creased_shell(unclamped, surface, creases);
    // A sheet: a clamped flat whose every piece is smaller than the bend's disc (Model C's
    // flutes dip 0.015 mm through the floor in eight spots of 0.03 mm^2) is no flat a tool
    // of that radius forms, and no fillet fits in it: there the sheet follows the family.
    Creases formed = creases;
    int unformed = 0;
    double unformed_depth_mm = 0.0;
    const auto unformable = [&](double z) {
        const std::vector<double> areas = flat_areas(shell, z);
        const bool small = !areas.empty() && *std::max_element(areas.begin(), areas.end()) <
                                                 std::numbers::pi * radius * radius;
        if (small) unformed += int(areas.size());
        return small;
    };
    const Holder& h = surface.holder();
    if (radius > 0.0 && formed.floor && unformable(h.min_mm.z)) {
        formed.floor = false;
        unformed_depth_mm = std::max(unformed_depth_mm, creases.below_floor_mm);
    }
    if (radius > 0.0 && formed.top && unformable(h.max_mm.z)) {
        formed.top = false;
        unformed_depth_mm = std::max(unformed_depth_mm, creases.above_top_mm);
    }
    if (unformed > 0) shell = formed.any() ? creased_shell(unclamped, surface, formed) : unclamped;
    r.edge_tolerance_mm = BRep_Tool::MaxTolerance(shell, TopAbs_EDGE);
    r = write_creased_part(shell, r, surface, formed.top || kink_bends_back, o, directory);
    if (r.bend) {
        r.bend->unformed_flats = unformed;
        r.bend->unformed_depth_mm = unformed_depth_mm;
    }
    return r;
}

// Writes the face (or its sheet) as STEP and the sampled grid as STL.
void write_part(const TopoDS_Shape& face, const SurfaceGrid& grid, const CadOptions& o,
                const std::string& directory, CadReport& r) {
    const TopoDS_Shape shape = reflector_shape(face, o.thickness_mm);
    create_output_directory(directory);
    const std::string step = file_in(directory, "reflector.step");
    write_step(shape, step);
    r.files.push_back({"reflector.step", std::filesystem::file_size(step)});
    const std::string stl = file_in(directory, "reflector.stl");
    r.files.push_back({"reflector.stl", write_reflector_stl(grid, o.thickness_mm, stl)});
}

// The profile family, exactly: its meridian revolved (cad_revolution), trimmed to the
// holder, creased where the holder clamps it.
CadReport export_revolved(const Surface& surface, const Creases& creases, const CadOptions& o,
                          const std::string& directory) {
    const ProfileFn& f = std::get<ProfileFn>(surface.function());
    const RevolvedProfile rev = revolve_profile(surface);
    CadReport r{.exact = true,
                .revolved = true,
                .trim_tolerance_mm = rev.trim_tolerance_mm,
                .max_deviation_mm = rev.max_deviation_mm,
                .worst_xy_mm = rev.worst_xy_mm,
                .fit_nx = f.spans + 1,
                .fit_ny = 1,
                .check_nx = rev.check_nu,
                .check_ny = rev.check_nv};
    // Eight STL samples in each of the profile's knot intervals (at least 129 an axis, at
    // most kMaxFitSamples), on the family itself; the back radius on twice as many.
    const Holder& h = surface.holder();
    const auto samples = [&](double extent) {
        return int(
            std::clamp(8.0 * std::ceil(extent / f.spacing) + 1.0, 129.0, double(kMaxFitSamples)));
    };
    const int stl_nx = samples(h.max_mm.x - h.min_mm.x), stl_ny = samples(h.max_mm.y - h.min_mm.y);
    measure_back_radius(r, rev.quarters, h, refined(stl_nx, 2), refined(stl_ny, 2));
    const bool kink_bends_back = rev.kink && rev.slope_at_radius > 0.0;
    if (creases.any())
        return export_creased(rev.faces, r, surface, creases, kink_bends_back, o, directory);
    // A sheet over the kink where the flat begins bends it as a crease.
    if (o.thickness_mm > 0.0 && rev.kink)
        return write_creased_part(rev.faces, r, surface, kink_bends_back, o, directory);
    r.stl_nx = stl_nx;
    r.stl_ny = stl_ny;
    refuse_folding_sheet(o, r);
    const SurfaceGrid grid = sample_family(surface, r.stl_nx, r.stl_ny);
    r.stl_chord_mm = chord_error_mm(grid, [&](double x, double y) { return surface.raw(x, y); });
    write_part(rev.faces, grid, o, directory, r);
    return r;
}

CadReport export_cad_unguarded(const Surface& surface, const CadOptions& o,
                               const std::string& directory) {
    if (!(o.tolerance_mm > 0.0))
        throw CadOptionError(fmt::format("--cad-tolerance {:g}: must be > 0 mm", o.tolerance_mm));
    if (!(o.thickness_mm >= 0.0))
        throw CadOptionError(fmt::format("--thickness {:g}: must be >= 0 mm (0: the surface alone)",
                                         o.thickness_mm));
    if (!(o.bend_radius_mm >= 0.0))
        throw CadOptionError(fmt::format(
            "--bend-radius {:g}: must be >= 0 mm (0: twice the thickness)", o.bend_radius_mm));
    if (o.bend_radius_mm > 0.0 && o.thickness_mm == 0.0)
        throw CadOptionError(fmt::format("--bend-radius {:g}: bends a sheet's creases, and needs "
                                         "--thickness (the surface alone has no bends)",
                                         o.bend_radius_mm));
    const bool mesh = std::holds_alternative<MeshFn>(surface.function());
    const Creases creases = mesh ? Creases{} : clamp_creases(surface);
    if (std::holds_alternative<ProfileFn>(surface.function()))
        return export_revolved(surface, creases, o, directory);
    if (creases.any()) {
        // A bend radius the sheet cannot take is refused before the fit (seconds at 1025^2).
        if (o.thickness_mm > 0.0) (void)bend_radius(o, creases.top);
        const CadSurface cad = make_cad_surface(surface, o.tolerance_mm, Heights::Unclamped);
        CadReport r = report_of(cad);
        // The family's bends where it is not clamped.
        measure_back_radius(r, std::span(&cad.surface, 1), surface.holder(),
                            refined(sheet_samples(cad, cad.fit_nx), 2),
                            refined(sheet_samples(cad, cad.fit_ny), 2));
        return export_creased(height_field_face(cad.surface), r, surface, creases, false, o,
                              directory);
    }
    const CadSurface cad = make_cad_surface(surface, o.tolerance_mm);
    CadReport r = report_of(cad);
    r.stl_nx = sheet_samples(cad, cad.fit_nx);
    r.stl_ny = sheet_samples(cad, cad.fit_ny);
    measure_back_radius(r, std::span(&cad.surface, 1), surface.holder(), refined(r.stl_nx, 2),
                        refined(r.stl_ny, 2));
    refuse_folding_sheet(o, r);
    const SurfaceGrid grid = sample_surface(cad.surface, r.stl_nx, r.stl_ny);
    // S(u, v) = (u, v, z): the surface point over (x, y) is at parameters (x, y).
    r.stl_chord_mm =
        chord_error_mm(grid, [&](double x, double y) { return cad.surface->Value(x, y).Z(); });
    write_part(height_field_face(cad.surface), grid, o, directory, r);
    return r;
}

} // namespace

CadReport export_cad(const Surface& surface, const CadOptions& o, const std::string& directory) {
    // One export at a time in a process: write_step sets OpenCASCADE's process-wide
    // translator options and messenger (the workbench writes on a thread of its own).
    static std::mutex one_at_a_time;
    const std::lock_guard lock(one_at_a_time);
    // OpenCASCADE throws Standard_Failure, which is no std::exception: one line, not an abort.
    try {
        return export_cad_unguarded(surface, o, directory);
    } catch (const Standard_Failure& e) {
        throw std::runtime_error(
            fmt::format("OpenCASCADE ({}): {}", e.DynamicType()->Name(), e.GetMessageString()));
    }
}

} // namespace fird
