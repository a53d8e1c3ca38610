// The manufacturability report (issue 27 item 3): the press's measures of a reflector
// (model/press_measures.hpp) and its [reflector.constraints] met or broken, as
// manufacturability.json, and a picture, manufacturability.png: the slope and the
// curvature over the holder seen from above, the worst point of each marked. Written by
// fird export --cad beside reflector.step and by fird optimize --out for the best reflector.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "model/press_measures.hpp"
#include "model/scene.hpp"
#include "model/surface.hpp"

namespace fird {

nlohmann::json manufacturability_json(const PressMeasures& m, const ConstraintsDesc& c);

// Needs the measures with their maps (PressOptions::maps).
void write_manufacturability_png(const std::string& path, const PressMeasures& m,
                                 const Holder& holder);

// Measures the surface and writes both files into `directory` (which must exist), each
// whole or not at all; returns the JSON written.
nlohmann::json write_manufacturability(const std::string& directory, const Surface& surface,
                                       const ConstraintsDesc& constraints);

} // namespace fird
