// A reflector clamped to the holder's z range as the part a press makes: the unclamped
// family (one smooth B-spline face) trimmed where it rises through the holder's top (or
// dips through its floor), and the flat flange (floor) beyond, meeting along their
// intersection curve (a crease). One smooth face would have to round the crease within
// the tolerance, which takes samples every few hundredths of a millimetre across the whole
// holder (docs/export.md).
#pragma once

#include <vector>

#include <TopoDS_Shape.hxx>

#include "model/surface.hpp"

namespace fird {

// Where the clamp acts: the family rises above the holder's top, dips below its floor
// (on a 257 x 257 grid: a clamp narrower than its step goes unseen and is fitted whole).
struct Creases {
    bool top = false, floor = false;
    // How far the family passes the top and the floor (mm, on the same grid).
    double above_top_mm = 0.0, below_floor_mm = 0.0;
    bool any() const { return top || floor; }
};
Creases clamp_creases(const Surface& surface);

// The areas of the shell's flat pieces at height z (the holder's top or floor), mm^2.
std::vector<double> flat_areas(const TopoDS_Shape& shell, double z);

// The shell of the trimmed face and the flat pieces, with shared crease edges; `unclamped`
// is the face (or shell) of the fitted (or exact) unclamped family over the holder
// rectangle, its normal up. Throws std::runtime_error where OpenCASCADE's boolean fails.
TopoDS_Shape creased_shell(const TopoDS_Shape& unclamped, const Surface& surface,
                           const Creases& creases);

} // namespace fird
