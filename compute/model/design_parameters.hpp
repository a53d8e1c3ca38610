// A search's parameters applied to a scene: a reflector parameter by its own name
// ([reflector.optimize]), a source parameter as "source.<key>" ([source.optimize]: the
// centre's x_mm, y_mm, z_mm, and tilt_x_deg, tilt_y_deg turning the source's axis and x axis
// about the scene's x, then y axis, from the scene's own orientation).
#pragma once

#include <map>
#include <string>

#include "model/scene.hpp"

namespace fird {

inline constexpr const char* kSourceParameterPrefix = "source.";

bool is_source_parameter(const std::string& name);
// A source parameter's key without the prefix ("source.x_mm" -> "x_mm").
std::string source_parameter_key(const std::string& name);

// `base` with the given source parameters (keys without the prefix).
SourceDesc moved_source(const SourceDesc& base, const std::map<std::string, double>& values);

// The scene with the named values: reflector parameters into its reflector, source ones
// (prefixed) into its source.
void apply_design_parameters(Scene& scene, const std::map<std::string, double>& named);

// A source parameter's value in the scene as it is (the centre's coordinate; 0 tilt).
double source_parameter_value(const SourceDesc& source, const std::string& key);

} // namespace fird
