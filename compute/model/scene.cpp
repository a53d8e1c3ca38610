#include "scene.hpp"

namespace fird {

const char* family_name(Family f) {
    switch (f) {
    case Family::Plane:
        return "plane";
    case Family::Paraboloid:
        return "paraboloid";
    case Family::Cup:
        return "cup";
    case Family::FlutedCup:
        return "fluted_cup";
    case Family::BSpline:
        return "bspline";
    case Family::Mesh:
        return "mesh";
    }
    return "?";
}

std::optional<Family> family_from_name(const std::string& name) {
    for (Family f : {Family::Plane, Family::Paraboloid, Family::Cup, Family::FlutedCup,
                     Family::BSpline, Family::Mesh})
        if (name == family_name(f)) return f;
    return std::nullopt;
}

std::vector<std::string> family_parameters(Family f) {
    switch (f) {
    case Family::Plane: // z = z0 + sx (x - cx) + sy (y - cy)
        return {"z0", "sx", "sy", "cx", "cy"};
    case Family::Paraboloid:
        return {"fx", "fy", "z0", "cx", "cy"};
    case Family::Cup:
        return {"a", "b", "p", "h", "z0", "cx", "cy"};
    case Family::FlutedCup:
        return {"a", "p", "h", "w", "z0", "cx", "cy"};
    case Family::BSpline:
    case Family::Mesh:
        return {};
    }
    return {};
}

namespace {
constexpr SearchMethod kMethods[] = {
    SearchMethod::Auto,   SearchMethod::Grid,    SearchMethod::Bobyqa, SearchMethod::Sbplx,
    SearchMethod::Cobyla, SearchMethod::DirectL, SearchMethod::Crs2};
} // namespace

const char* method_name(SearchMethod m) {
    switch (m) {
    case SearchMethod::Auto:
        return "auto";
    case SearchMethod::Grid:
        return "grid";
    case SearchMethod::Bobyqa:
        return "bobyqa";
    case SearchMethod::Sbplx:
        return "sbplx";
    case SearchMethod::Cobyla:
        return "cobyla";
    case SearchMethod::DirectL:
        return "direct";
    case SearchMethod::Crs2:
        return "crs2";
    }
    return "?";
}

std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (SearchMethod m : kMethods)
        names.emplace_back(method_name(m));
    return names;
}

std::optional<SearchMethod> method_from_name(const std::string& name) {
    for (SearchMethod m : kMethods)
        if (name == method_name(m)) return m;
    return std::nullopt;
}

ReflectorDesc target_reflector(const Scene& scene) {
    ReflectorDesc r = scene.reflector;
    for (const auto& [k, v] : scene.target.parameters)
        r.parameters[k] = v;
    return r;
}

} // namespace fird
