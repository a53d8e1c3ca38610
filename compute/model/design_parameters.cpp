#include "design_parameters.hpp"

#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace fird {

namespace {
// v turned by `deg` about the unit axis a (Rodrigues' formula).
glm::dvec3 turned(const glm::dvec3& v, const glm::dvec3& a, double deg) {
    const double t = glm::radians(deg);
    return v * std::cos(t) + glm::cross(a, v) * std::sin(t) +
           a * glm::dot(a, v) * (1.0 - std::cos(t));
}
} // namespace

bool is_source_parameter(const std::string& name) {
    return name.rfind(kSourceParameterPrefix, 0) == 0;
}

std::string source_parameter_key(const std::string& name) {
    return name.substr(std::string(kSourceParameterPrefix).size());
}

SourceDesc moved_source(const SourceDesc& base, const std::map<std::string, double>& values) {
    SourceDesc s = base;
    double tilt_x = 0.0, tilt_y = 0.0;
    for (const auto& [key, v] : values) {
        if (key == "x_mm")
            s.center_mm.x = v;
        else if (key == "y_mm")
            s.center_mm.y = v;
        else if (key == "z_mm")
            s.center_mm.z = v;
        else if (key == "tilt_x_deg")
            tilt_x = v;
        else if (key == "tilt_y_deg")
            tilt_y = v;
        else
            throw std::invalid_argument("not a source parameter: " + key);
    }
    for (const auto& [a, deg] :
         {std::pair{glm::dvec3(1, 0, 0), tilt_x}, std::pair{glm::dvec3(0, 1, 0), tilt_y}}) {
        if (deg == 0.0) continue;
        s.axis = glm::normalize(turned(s.axis, a, deg));
        s.x_axis = glm::normalize(turned(s.x_axis, a, deg));
    }
    return s;
}

void apply_design_parameters(Scene& scene, const std::map<std::string, double>& named) {
    std::map<std::string, double> source;
    for (const auto& [name, v] : named) {
        if (is_source_parameter(name))
            source[source_parameter_key(name)] = v;
        else
            scene.reflector.parameters[name] = v;
    }
    if (!source.empty()) scene.source = moved_source(scene.source, source);
}

double source_parameter_value(const SourceDesc& source, const std::string& key) {
    if (key == "x_mm") return source.center_mm.x;
    if (key == "y_mm") return source.center_mm.y;
    if (key == "z_mm") return source.center_mm.z;
    return 0.0; // a tilt: from the scene's own orientation
}

} // namespace fird
