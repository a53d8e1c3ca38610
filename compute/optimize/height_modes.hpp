// The coordinates a population search samples a reflector's free heights in: the cosine
// modes of a freed height grid (a bspline's control heights, a profile's heights), the
// broad shapes weighted above the fine ones, instead of each height on its own.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "model/scene.hpp"
#include "optimize/parameter_space.hpp"

namespace fird {

// parameters = origin + transform c. Where a grid of heights is free, its coordinates are
// the grid's cosine modes (a discrete cosine transform, DCT-II, orthonormal), mode (kx, ky)
// scaled so that a unit coefficient moves the heights by (1 + kx + ky)^-2 mm RMS: a
// generation's candidates differ first in the surface's broad shape, and CMA-ES's
// covariance learns finer detail where the far field rewards it. The basis is complete, so
// every surface of the box can still be reached (no smoothness is imposed on the result).
// The other parameters (a profile's z0, a source's) are coordinates of their own, as
// offsets from the start like the modes.
struct SampleCoordinates {
    std::vector<double> origin;    // the parameters at c = 0 (the search's start)
    std::vector<double> transform; // size() x size(), row-major; empty: c are the parameters
    std::vector<double> lo, hi;    // the coordinates' box (the population's bounds)
    std::size_t modes = 0;         // how many coordinates are a grid's modes (0: none)
    // Per coordinate, how broad a shape it is: kx + ky of a mode (0 the mean height, 1 the
    // tilts, ...), 0 for a coordinate that is a parameter of its own.
    std::vector<std::size_t> degree;
    std::string grid; // the grid they are the modes of, e.g. "6 x 6" ("" if none)

    std::size_t size() const { return origin.size(); }
    std::vector<double> parameters(const std::vector<double>& c) const;
};

// The modes where every height of the reflector's grid (h_<i>_<j> of a bspline, h_<k> of a
// profile) is free and `sampling` asks for them, else each parameter as it is. `start` is
// the search's start, in the space's order.
SampleCoordinates sample_coordinates(const ReflectorDesc& reflector, const ParameterSpace& space,
                                     const std::vector<double>& start, HeightSampling sampling);

} // namespace fird
