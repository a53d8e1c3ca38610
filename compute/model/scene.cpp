#include "scene.hpp"

namespace fird {

namespace {

// The names of an enumeration's values in scene files and on the command line: one table
// per enumeration, read both ways.
template <typename E> struct Named {
    E value;
    const char* name;
};

constexpr Named<Family> kFamilies[] = {
    {Family::Plane, "plane"},          {Family::Paraboloid, "paraboloid"}, {Family::Cup, "cup"},
    {Family::FlutedCup, "fluted_cup"}, {Family::BSpline, "bspline"},       {Family::Mesh, "mesh"},
    {Family::Profile, "profile"}};
constexpr Named<SearchMethod> kMethods[] = {
    {SearchMethod::Auto, "auto"},     {SearchMethod::Grid, "grid"},
    {SearchMethod::Bobyqa, "bobyqa"}, {SearchMethod::Sbplx, "sbplx"},
    {SearchMethod::Cobyla, "cobyla"}, {SearchMethod::DirectL, "direct"},
    {SearchMethod::Crs2, "crs2"},     {SearchMethod::Cmaes, "cmaes"},
    {SearchMethod::Xnes, "xnes"},     {SearchMethod::Levenberg, "levenberg"}};
constexpr Named<SamplerKind> kSamplers[] = {{SamplerKind::Stratified, "stratified"},
                                            {SamplerKind::Random, "random"},
                                            {SamplerKind::Sobol, "sobol"}};

template <typename E, std::size_t N> const char* name_of(const Named<E> (&table)[N], E value) {
    for (const Named<E>& n : table)
        if (n.value == value) return n.name;
    return "?";
}

template <typename E, std::size_t N>
std::optional<E> value_of(const Named<E> (&table)[N], const std::string& name) {
    for (const Named<E>& n : table)
        if (name == n.name) return n.value;
    return std::nullopt;
}

template <typename E, std::size_t N> std::vector<std::string> names_of(const Named<E> (&table)[N]) {
    std::vector<std::string> names;
    for (const Named<E>& n : table)
        names.emplace_back(n.name);
    return names;
}

} // namespace

const char* family_name(Family f) {
    return name_of(kFamilies, f);
}
std::optional<Family> family_from_name(const std::string& name) {
    return value_of(kFamilies, name);
}

const char* method_name(SearchMethod m) {
    return name_of(kMethods, m);
}
std::vector<std::string> method_names() {
    return names_of(kMethods);
}
std::optional<SearchMethod> method_from_name(const std::string& name) {
    return value_of(kMethods, name);
}

const char* source_type_name(SourceKind kind) {
    switch (kind) {
    case SourceKind::Cylinder:
        return "cylinder";
    case SourceKind::Sphere:
        return "sphere";
    case SourceKind::Point:
        return "point";
    case SourceKind::Disk:
        return "disk";
    case SourceKind::Rectangle:
        return "rectangle";
    case SourceKind::Photometric:
        return "photometric";
    case SourceKind::RayFile:
        return "rayfile";
    }
    return "point";
}

const char* sampler_name(SamplerKind s) {
    return name_of(kSamplers, s);
}
std::vector<std::string> sampler_names() {
    return names_of(kSamplers);
}
std::optional<SamplerKind> sampler_from_name(const std::string& name) {
    return value_of(kSamplers, name);
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
    case Family::Profile: // z = z0 + f(|(x, y) - (cx, cy)|), f through the heights
        return {"z0", "cx", "cy", "radius_mm"};
    case Family::BSpline:
    case Family::Mesh:
        return {};
    }
    return {};
}

ReflectorDesc target_reflector(const Scene& scene) {
    ReflectorDesc r = scene.reflector;
    for (const auto& [k, v] : scene.target.parameters)
        r.parameters[k] = v;
    return r;
}

} // namespace fird
