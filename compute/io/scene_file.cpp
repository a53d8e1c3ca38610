#include "scene_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <toml++/toml.h>

#include <glm/geometric.hpp>

#include "model/emission_table.hpp"
#include "model/ray_file_source.hpp"
#include "model/source.hpp"
#include "model/source_clearance.hpp"
#include "model/surface.hpp"
#include "model/tolerance_check.hpp"
#include "photometry/photometry_file.hpp"

namespace fird {

namespace {

// Reads one TOML table, reporting errors as "file:line: [table] key: message".
class TableReader {
  public:
    TableReader(const std::string& file, const toml::table& table, std::string name)
        : file_(file), table_(table), name_(std::move(name)) {}

    [[noreturn]] void fail(const toml::node* node, const std::string& key,
                           const std::string& message) const {
        const auto line = node ? node->source().begin.line : table_.source().begin.line;
        throw SceneError(fmt::format("{}:{}: [{}] {}{}{}", file_, line, name_, key,
                                     key.empty() ? "" : ": ", message));
    }

    void allow_only(const std::set<std::string>& allowed) const {
        for (const auto& [k, v] : table_)
            if (!allowed.count(std::string(k.str()))) fail(&v, std::string(k.str()), "unknown key");
    }

    const toml::node* find(const std::string& key) const { return table_.get(key); }
    bool has(const std::string& key) const { return find(key) != nullptr; }

    const toml::node& need(const std::string& key) const {
        const toml::node* n = find(key);
        if (!n) fail(nullptr, key, "required key is missing");
        return *n;
    }

    double number(const std::string& key, const toml::node& n) const {
        double v = 0.0;
        if (auto i = n.as_integer())
            v = double(i->get());
        else if (auto f = n.as_floating_point())
            v = f->get();
        else
            fail(&n, key, "must be a number");
        if (!std::isfinite(v)) fail(&n, key, "must be finite");
        return v;
    }
    double number(const std::string& key) const { return number(key, need(key)); }
    double number_or(const std::string& key, double fallback) const {
        return has(key) ? number(key) : fallback;
    }
    double positive(const std::string& key) const {
        const double v = number(key);
        if (!(v > 0.0)) fail(find(key), key, "must be > 0");
        return v;
    }

    std::int64_t integer(const std::string& key, std::int64_t lo, std::int64_t hi) const {
        const toml::node& n = need(key);
        const auto i = n.as_integer();
        if (!i) fail(&n, key, "must be an integer");
        const std::int64_t v = i->get();
        if (v < lo || v > hi) fail(&n, key, fmt::format("must be between {} and {}", lo, hi));
        return v;
    }

    std::string text(const std::string& key) const {
        const toml::node& n = need(key);
        const auto s = n.as_string();
        if (!s) fail(&n, key, "must be a string");
        return s->get();
    }
    std::string choice(const std::string& key, const std::vector<std::string>& options,
                       const std::string& fallback) const {
        if (!has(key)) return fallback;
        const std::string v = text(key);
        if (std::find(options.begin(), options.end(), v) == options.end())
            fail(find(key), key, fmt::format("must be one of: {}", fmt::join(options, ", ")));
        return v;
    }
    bool boolean_or(const std::string& key, bool fallback) const {
        if (!has(key)) return fallback;
        const auto b = find(key)->as_boolean();
        if (!b) fail(find(key), key, "must be true or false");
        return b->get();
    }

    // One whole number in [lo, hi], or an array of them.
    std::vector<std::int64_t> integers(const std::string& key, std::int64_t lo,
                                       std::int64_t hi) const {
        const toml::node& n = need(key);
        const auto check = [&](const toml::node& e) {
            const auto i = e.as_integer();
            if (!i || i->get() < lo || i->get() > hi)
                fail(&e, key,
                     fmt::format("must be a whole number between {} and {}, or an array of them",
                                 lo, hi));
            return i->get();
        };
        if (const auto arr = n.as_array()) {
            if (arr->empty()) fail(&n, key, "must not be an empty array");
            std::vector<std::int64_t> out;
            for (const auto& e : *arr)
                out.push_back(check(e));
            return out;
        }
        return {check(n)};
    }

    std::vector<double> numbers(const std::string& key, std::size_t count) const {
        const toml::node& n = need(key);
        const auto arr = n.as_array();
        if (!arr || (count && arr->size() != count))
            fail(&n, key,
                 count ? fmt::format("must be an array of {} numbers", count)
                       : "must be an array of numbers");
        std::vector<double> out;
        for (const auto& e : *arr)
            out.push_back(number(key, e));
        return out;
    }
    glm::dvec3 vec3(const std::string& key) const {
        const auto v = numbers(key, 3);
        return {v[0], v[1], v[2]};
    }
    std::pair<std::uint32_t, std::uint32_t> size2(const std::string& key, std::uint32_t max) const {
        const auto v = numbers(key, 2);
        for (double d : v)
            if (d != std::floor(d) || d < 1 || d > max)
                fail(find(key), key,
                     fmt::format("must be two whole numbers between 1 and {}", max));
        return {std::uint32_t(v[0]), std::uint32_t(v[1])};
    }

    TableReader sub(const std::string& key) const {
        const toml::node& n = need(key);
        const auto t = n.as_table();
        if (!t) fail(&n, key, "must be a table");
        return {file_, *t, name_.empty() ? key : name_ + "." + key};
    }
    const toml::table& table() const { return table_; }
    const std::string& file() const { return file_; }

  private:
    const std::string& file_;
    const toml::table& table_;
    std::string name_;
};

// v made unit; one already unit to rounding kept bit for bit (so that a scene written back
// by scene_to_toml reads as the same scene).
glm::dvec3 made_unit(const glm::dvec3& v) {
    return std::abs(glm::length(v) - 1.0) < 1e-14 ? v : glm::normalize(v);
}

// A disk's or rectangle's orientation: `normal` (default [0, 0, 1]) and `x_axis` (default
// model/source.hpp's default_x_axis), both made unit, x_axis made perpendicular to normal.
void read_emitter_frame(const TableReader& t, SourceDesc& s) {
    s.axis = t.has("normal") ? t.vec3("normal") : glm::dvec3(0.0, 0.0, 1.0);
    if (!(glm::length(s.axis) > 0.0))
        t.fail(t.find("normal"), "normal", "must not be the zero vector");
    s.axis = made_unit(s.axis);
    if (!t.has("x_axis")) {
        s.x_axis = default_x_axis(s.axis);
        return;
    }
    const glm::dvec3 x = t.vec3("x_axis");
    const double along = glm::dot(x, s.axis);
    const glm::dvec3 across = std::abs(along) < 1e-14 ? x : x - along * s.axis;
    // Within a thousandth of a radian of the normal, the side's direction is undefined.
    if (!(glm::length(across) > 1e-3 * glm::length(x)))
        t.fail(t.find("x_axis"), "x_axis", "must not be parallel to the normal (nor zero)");
    s.x_axis = made_unit(across);
}

// A ray file source: its file indexed (read through once), its frame, its flux (the file's
// unless flux_lm rescales it) and `subsample`, returned: the fraction of the file's rays
// emitted where [trace] sets no rays.
void read_ray_file_source(const TableReader& t, const std::string& scene_path, SourceDesc& s,
                          std::optional<double>& subsample) {
    t.allow_only(
        {"optimize", "type", "center_mm", "normal", "x_axis", "file", "subsample", "flux_lm"});
    s.kind = SourceKind::RayFile;
    read_emitter_frame(t, s);
    if (t.has("subsample")) {
        subsample = t.number("subsample");
        if (!(*subsample > 0.0 && *subsample <= 1.0))
            t.fail(t.find("subsample"), "subsample", "must be > 0 and <= 1");
    }
    s.file = t.text("file");
    s.resolved_path = resolve_beside(scene_path, s.file);
    try {
        s.ray_file.index = index_ray_file(s.resolved_path);
    } catch (const std::exception& e) {
        t.fail(t.find("file"), "file", e.what());
    }
    if (t.has("flux_lm")) {
        s.flux_lm = t.positive("flux_lm");
    } else if (std::isfinite(s.ray_file.index->file_flux_lm)) {
        s.flux_lm = s.ray_file.index->file_flux_lm;
    } else {
        t.fail(t.find("file"), "flux_lm",
               "the ray file gives no luminous flux (no lumens per ray, none in a header): "
               "give flux_lm");
    }
}

SourceDesc read_source(const TableReader& t, const std::string& scene_path,
                       std::optional<double>& subsample) {
    SourceDesc s;
    const std::string type = t.choice(
        "type", {"cylinder", "sphere", "point", "disk", "rectangle", "photometric", "rayfile"}, "");
    if (type.empty()) t.need("type");
    s.center_mm = t.vec3("center_mm");
    if (type == "rayfile") {
        read_ray_file_source(t, scene_path, s, subsample);
        return s;
    }
    if (type == "photometric") {
        // The file's own flux unless flux_lm rescales it (its distribution is kept).
        t.allow_only(
            {"optimize", "type", "center_mm", "normal", "x_axis", "radius_mm", "file", "flux_lm"});
        s.kind = SourceKind::Photometric;
        read_emitter_frame(t, s);
        s.radius_mm = t.number_or("radius_mm", 0.0);
        if (s.radius_mm < 0.0) t.fail(t.find("radius_mm"), "radius_mm", "must be >= 0");
        s.file = t.text("file");
        s.resolved_path = resolve_beside(scene_path, s.file);
        try {
            const CandelaTable table = read_photometry(s.resolved_path);
            s.table = emission_table(table);
            s.flux_lm = t.has("flux_lm") ? t.positive("flux_lm") : integrated_flux_lm(table);
        } catch (const SceneError&) {
            throw;
        } catch (const std::exception& e) {
            t.fail(t.find("file"), "file", e.what());
        }
        return s;
    }
    s.flux_lm = t.positive("flux_lm");
    if (type == "cylinder") {
        t.allow_only({"optimize", "type", "center_mm", "axis", "length_mm", "radius_mm",
                      "emittance", "flux_lm"});
        s.kind = SourceKind::Cylinder;
        s.axis = t.vec3("axis");
        s.length_mm = t.positive("length_mm");
        s.radius_mm = t.positive("radius_mm");
        t.choice("emittance", {"cosine"}, "cosine");
    } else if (type == "sphere") {
        t.allow_only({"optimize", "type", "center_mm", "radius_mm", "emittance", "flux_lm"});
        s.kind = SourceKind::Sphere;
        s.radius_mm = t.positive("radius_mm");
        t.choice("emittance", {"cosine"}, "cosine");
    } else if (type == "disk") {
        t.allow_only({"optimize", "type", "center_mm", "normal", "x_axis", "radius_mm", "emittance",
                      "flux_lm"});
        s.kind = SourceKind::Disk;
        read_emitter_frame(t, s);
        s.radius_mm = t.positive("radius_mm");
        t.choice("emittance", {"cosine"}, "cosine");
    } else if (type == "rectangle") {
        t.allow_only({"optimize", "type", "center_mm", "normal", "x_axis", "size_mm", "emittance",
                      "flux_lm"});
        s.kind = SourceKind::Rectangle;
        read_emitter_frame(t, s);
        const std::vector<double> size = t.numbers("size_mm", 2);
        if (!(size[0] > 0.0 && size[1] > 0.0))
            t.fail(t.find("size_mm"), "size_mm", "both sides must be > 0");
        s.width_mm = size[0];
        s.height_mm = size[1];
        t.choice("emittance", {"cosine"}, "cosine");
    } else {
        t.allow_only({"optimize", "type", "center_mm", "axis", "emittance", "flux_lm"});
        s.kind = SourceKind::Point;
        s.emittance = t.choice("emittance", {"cosine", "isotropic"}, "isotropic") == "cosine"
                          ? Emittance::Cosine
                          : Emittance::Isotropic;
        if (s.emittance == Emittance::Cosine) s.axis = t.vec3("axis");
    }
    if ((s.kind == SourceKind::Cylinder ||
         (s.kind == SourceKind::Point && s.emittance == Emittance::Cosine)) &&
        glm::dvec3(s.axis) == glm::dvec3(0.0))
        t.fail(t.find("axis"), "axis", "must not be the zero vector");
    return s;
}

Holder read_holder(const TableReader& t) {
    t.allow_only({"min_mm", "max_mm"});
    Holder h{t.vec3("min_mm"), t.vec3("max_mm")};
    for (int k = 0; k < 3; ++k)
        if (!(h.min_mm[k] < h.max_mm[k]))
            t.fail(t.find("max_mm"), "max_mm",
                   fmt::format("the holder box is empty: max_mm[{}] = {} is not greater than "
                               "min_mm[{}] = {}",
                               k, h.max_mm[k], k, h.min_mm[k]));
    return h;
}

ParameterRange read_range(const TableReader& opt, const std::string& name);

// [source.optimize]: the centre's coordinates and, for a source with an axis, its tilts.
std::map<std::string, ParameterRange> read_source_optimize(const TableReader& opt,
                                                           const SourceDesc& source) {
    std::map<std::string, ParameterRange> out;
    const bool has_axis = source_has_axis(source);
    for (const auto& [k, v] : opt.table()) {
        const std::string name(k.str());
        const bool tilt = name == "tilt_x_deg" || name == "tilt_y_deg";
        if (!(name == "x_mm" || name == "y_mm" || name == "z_mm" || tilt))
            opt.fail(&v, name,
                     "is not a source parameter (x_mm, y_mm, z_mm, tilt_x_deg, "
                     "tilt_y_deg)");
        if (tilt && !has_axis)
            opt.fail(&v, name,
                     fmt::format("a {} source has no axis to tilt", source_type_name(source.kind)));
        out[name] = read_range(opt, name);
        if (tilt && (out[name].min < -90.0 || out[name].max > 90.0))
            opt.fail(&v, name, "must stay within -90 and 90 degrees");
    }
    return out;
}

ParameterRange read_range(const TableReader& opt, const std::string& name) {
    const TableReader range = opt.sub(name);
    range.allow_only({"min", "max", "step"});
    ParameterRange pr{range.number("min"), range.number("max"), range.number("step")};
    if (pr.min > pr.max) range.fail(range.find("max"), "max", "must not be below min");
    if (!(pr.step > 0.0)) range.fail(range.find("step"), "step", "must be > 0");
    return pr;
}

// [reflector.optimize] heights_mm = { min, max, step }: every control height of the B-spline
// free, each a point group named h_<i>_<j> (column i, row j) with that range, so the
// search, history.csv and the JSON name each height. Groups of one's own would set the same
// heights as these (the last by name winning), so the two are not mixed.
void free_every_height(const TableReader& opt, ReflectorDesc& r) {
    if (!r.bspline.groups.empty())
        opt.fail(opt.find("heights_mm"), "heights_mm",
                 fmt::format("frees every control height, so it cannot be combined with "
                             "[reflector.groups] ({} would set the same heights)",
                             r.bspline.groups.begin()->first));
    const ParameterRange range = read_range(opt, "heights_mm");
    for (int j = 0; j < r.bspline.ny; ++j)
        for (int i = 0; i < r.bspline.nx; ++i) {
            const std::string name = fmt::format("h_{}_{}", i, j);
            r.bspline.groups[name] = {.kind = ControlGroup::Kind::Point, .i = i, .j = j};
            r.optimize[name] = range;
        }
}

// [reflector.material]: the finish every reflection applies (shaders/material.h).
MaterialDesc read_material(const TableReader& t) {
    t.allow_only({"reflectance", "spread_deg", "lobe"});
    MaterialDesc m;
    m.reflectance = t.number_or("reflectance", 1.0);
    if (!(m.reflectance >= 0.0 && m.reflectance <= 1.0))
        t.fail(t.find("reflectance"), "reflectance", "must be between 0 and 1");
    m.spread_deg = t.number_or("spread_deg", 0.0);
    if (!(m.spread_deg >= 0.0 && m.spread_deg <= kMaxSpread_deg))
        t.fail(t.find("spread_deg"), "spread_deg",
               fmt::format("must be between 0 and {} degrees", kMaxSpread_deg));
    m.lobe = t.choice("lobe", {"gaussian", "phong"}, "gaussian") == "phong" ? SpreadLobe::Phong
                                                                            : SpreadLobe::Gaussian;
    return m;
}

// [reflector.constraints]: what the press can form (model/press_measures.hpp), each optional.
ConstraintsDesc read_constraints(const TableReader& t) {
    t.allow_only({"max_slope_deg", "min_radius_mm", "max_depth_mm"});
    ConstraintsDesc c;
    if (t.has("max_slope_deg")) {
        c.max_slope_deg = t.number("max_slope_deg");
        // 90 degrees is a vertical wall, which a height field cannot have anyway.
        if (!(*c.max_slope_deg > 0.0 && *c.max_slope_deg < 90.0))
            t.fail(t.find("max_slope_deg"), "max_slope_deg",
                   "must be between 0 and 90 degrees (exclusive)");
    }
    if (t.has("min_radius_mm")) c.min_radius_mm = t.positive("min_radius_mm");
    if (t.has("max_depth_mm")) c.max_depth_mm = t.positive("max_depth_mm");
    return c;
}

// The profile family: z0, cx, cy, radius_mm, and heights_mm, an array of at least two (the
// profile's heights at radii 0 .. radius_mm evenly spaced) or one number for every height
// with their count in `grid`. Each height is a parameter h_<k> (a point group), its value
// optional in [reflector] (overriding heights_mm) and free in [reflector.optimize], or all
// at once by heights_mm = { min, max, step } there.
void read_profile(const TableReader& t, ReflectorDesc& r, std::vector<std::string>& params,
                  std::set<std::string>& allowed) {
    for (const auto& p : params) {
        allowed.insert(p);
        r.parameters[p] = t.number(p);
    }
    if (!(r.parameters["radius_mm"] > 0.0)) t.fail(t.find("radius_mm"), "radius_mm", "must be > 0");
    allowed.insert({"grid", "heights_mm"});
    const toml::node& h = t.need("heights_mm");
    if (h.is_integer() || h.is_floating_point()) {
        if (!t.has("grid"))
            t.fail(&h, "heights_mm", "is one number, so `grid` must give how many heights");
        const auto count = t.integer("grid", 2, kMaxProfileHeights);
        r.bspline.heights_mm.assign(std::size_t(count), t.number("heights_mm", h));
    } else if (!h.is_array()) {
        t.fail(&h, "heights_mm", "must be an array of heights or one number (with `grid`)");
    } else {
        r.bspline.heights_mm = t.numbers("heights_mm", 0);
        if (r.bspline.heights_mm.size() < 2 || r.bspline.heights_mm.size() > kMaxProfileHeights)
            t.fail(&h, "heights_mm",
                   fmt::format("must hold between 2 and {} heights (a cubic spline through "
                               "them from the axis to radius_mm)",
                               kMaxProfileHeights));
        if (t.has("grid") &&
            std::size_t(t.integer("grid", 2, kMaxProfileHeights)) != r.bspline.heights_mm.size())
            t.fail(t.find("grid"), "grid", "must equal the number of heights_mm");
    }
    r.bspline.nx = int(r.bspline.heights_mm.size());
    r.bspline.ny = 1;
    for (int k = 0; k < r.bspline.nx; ++k) {
        const std::string name = fmt::format("h_{}", k);
        r.bspline.groups[name] = {.kind = ControlGroup::Kind::Point, .i = k, .j = 0};
        params.push_back(name);
        allowed.insert(name);
        if (t.has(name)) r.parameters[name] = t.number(name);
    }
}

ReflectorDesc read_reflector(const TableReader& t, const std::string& scene_path) {
    ReflectorDesc r;
    const std::string family = t.text("family");
    const auto f = family_from_name(family);
    if (!f)
        t.fail(t.find("family"), "family",
               "must be one of: plane, paraboloid, cup, fluted_cup, bspline, profile, mesh");
    r.family = *f;
    std::set<std::string> allowed = {"family", "optimize", "material", "constraints"};
    std::vector<std::string> params = family_parameters(r.family);
    if (r.family == Family::BSpline) {
        allowed.insert({"grid", "heights_mm", "groups"});
        const auto grid = t.size2("grid", 1024);
        r.bspline.nx = int(grid.first);
        r.bspline.ny = int(grid.second);
        if (r.bspline.nx < 2 || r.bspline.ny < 2)
            t.fail(t.find("grid"), "grid", "needs at least 2 x 2 control heights");
        const std::size_t count = std::size_t(r.bspline.nx) * r.bspline.ny;
        // One number starts every control height there (a flat start for a freeform search).
        if (const toml::node* h = t.find("heights_mm");
            h && (h->is_integer() || h->is_floating_point()))
            r.bspline.heights_mm.assign(count, t.number("heights_mm", *h));
        else if (h && !h->is_array())
            t.fail(h, "heights_mm",
                   fmt::format("must be one number (every control height) or an array of {} "
                               "numbers",
                               count));
        else
            r.bspline.heights_mm = t.numbers("heights_mm", count);
        if (t.has("groups")) {
            const TableReader groups = t.sub("groups");
            for (const auto& [k, v] : groups.table()) {
                const std::string name(k.str());
                const TableReader g = groups.sub(name);
                ControlGroup cg;
                const std::string kind = g.choice("kind", {"point", "row", "column", "ring"}, "");
                if (kind.empty()) g.need("kind");
                if (kind == "point") {
                    g.allow_only({"kind", "i", "j"});
                    cg.kind = ControlGroup::Kind::Point;
                    cg.i = int(g.integer("i", 0, r.bspline.nx - 1));
                    cg.j = int(g.integer("j", 0, r.bspline.ny - 1));
                } else {
                    g.allow_only({"kind", "index"});
                    cg.kind = kind == "row"      ? ControlGroup::Kind::Row
                              : kind == "column" ? ControlGroup::Kind::Column
                                                 : ControlGroup::Kind::Ring;
                    const int limit = kind == "row" ? r.bspline.ny - 1
                                      : kind == "column"
                                          ? r.bspline.nx - 1
                                          : (std::min(r.bspline.nx, r.bspline.ny) - 1) / 2;
                    cg.i = int(g.integer("index", 0, limit));
                }
                r.bspline.groups[name] = cg;
                params.push_back(name);
            }
        }
        // Group values are optional: without one, the group keeps heights_mm.
        for (const auto& [name, group] : r.bspline.groups) {
            allowed.insert(name);
            if (t.has(name)) r.parameters[name] = t.number(name);
        }
    } else if (r.family == Family::Profile) {
        read_profile(t, r, params, allowed);
    } else if (r.family == Family::Mesh) {
        allowed.insert({"file", "unit_mm"});
        r.mesh.file = t.text("file");
        r.mesh.resolved_path = resolve_beside(scene_path, r.mesh.file);
        r.mesh.unit_mm = t.has("unit_mm") ? t.positive("unit_mm") : 1.0;
    } else {
        for (const auto& p : params) {
            allowed.insert(p);
            r.parameters[p] = t.number(p);
        }
    }
    t.allow_only(allowed);
    if (t.has("material")) r.material = read_material(t.sub("material"));
    if (t.has("constraints")) r.constraints = read_constraints(t.sub("constraints"));
    if (t.has("optimize")) {
        const TableReader opt = t.sub("optimize");
        for (const auto& [k, v] : opt.table()) {
            const std::string name(k.str());
            if (r.family == Family::BSpline && name == "heights_mm") {
                free_every_height(opt, r);
                continue;
            }
            if (r.family == Family::Profile && name == "heights_mm") {
                for (const auto& [h, group] : r.bspline.groups)
                    if (opt.has(h))
                        opt.fail(opt.find("heights_mm"), "heights_mm",
                                 fmt::format("frees every height, so it cannot be combined with "
                                             "{} (both would bound the same height)",
                                             h));
                const ParameterRange range = read_range(opt, name);
                for (const auto& [h, group] : r.bspline.groups)
                    r.optimize[h] = range;
                continue;
            }
            if (std::find(params.begin(), params.end(), name) == params.end())
                opt.fail(&v, name, fmt::format("is not a parameter of the {} family", family));
            r.optimize[name] = read_range(opt, name);
        }
    }
    return r;
}

// [tolerance]: fird tolerance's defaults (its options override them).
ToleranceDesc read_tolerance(const TableReader& t, const SourceDesc& source) {
    t.allow_only({"realisations", "source_shift_mm", "source_tilt_deg", "surface_rms_mm",
                  "surface_correlation_mm", "reflectance_sd"});
    ToleranceDesc d;
    if (t.has("realisations"))
        d.realisations = std::uint64_t(t.integer("realisations", 1, 1000000));
    if (const toml::node* n = t.find("source_shift_mm"); n && n->is_array())
        d.source_shift_mm = t.vec3("source_shift_mm");
    else if (n)
        d.source_shift_mm = glm::dvec3(t.number("source_shift_mm"));
    for (int k = 0; k < 3; ++k)
        if (d.source_shift_mm[k] < 0.0)
            t.fail(t.find("source_shift_mm"), "source_shift_mm", "must be >= 0");
    const auto non_negative = [&](const char* key) {
        const double v = t.number_or(key, 0.0);
        if (v < 0.0) t.fail(t.find(key), key, "must be >= 0");
        return v;
    };
    d.source_tilt_deg = non_negative("source_tilt_deg");
    d.surface_rms_mm = non_negative("surface_rms_mm");
    d.surface_correlation_mm = non_negative("surface_correlation_mm");
    d.reflectance_sd = non_negative("reflectance_sd");
    if (const auto problem = tolerance_problem(d, source))
        t.fail(t.find(problem->key == "surface_correlation_mm" ? "surface_rms_mm"
                                                               : problem->key.c_str()),
               problem->key.c_str(), problem->reason);
    return d;
}

// `file_rays`: a ray file source's emission count where `rays` is not given (its rays
// times its subsample); `subsample_given`: the source set subsample, so rays may not.
TraceSettings read_trace(const TableReader& t, std::optional<std::uint64_t> file_rays,
                         bool subsample_given) {
    t.allow_only({"rays", "seed", "max_bounces", "bounce_policy", "sampler", "hit_mode", "direct",
                  "heightfield", "farfield"});
    TraceSettings s;
    if (file_rays && !t.has("rays"))
        s.rays = *file_rays;
    else
        s.rays = std::uint64_t(t.integer("rays", 1, 10'000'000'000));
    if (subsample_given && t.has("rays"))
        t.fail(t.find("rays"), "rays",
               "a ray file source with subsample emits that share of its rays: give rays or "
               "[source] subsample, not both");
    s.seed = std::uint64_t(t.has("seed") ? t.integer("seed", 0, INT64_MAX) : 1);
    s.max_bounces = std::uint32_t(t.integer("max_bounces", 1, 64));
    s.bounce_policy = t.choice("bounce_policy", {"paper", "strict"}, "paper") == "strict"
                          ? BouncePolicy::Strict
                          : BouncePolicy::Paper;
    s.sampler = *sampler_from_name(t.choice("sampler", sampler_names(), "stratified"));
    s.hit_mode = t.choice("hit_mode", {"paper", "refined"}, "refined") == "paper"
                     ? HitMode::Paper
                     : HitMode::Refined;
    s.direct = t.choice("direct", {"exclude", "include"}, "exclude") == "include"
                   ? DirectLight::Include
                   : DirectLight::Exclude;
    if (t.has("heightfield"))
        std::tie(s.heightfield_w, s.heightfield_h) = t.size2("heightfield", 16384);
    if (t.has("farfield")) std::tie(s.farfield_w, s.farfield_h) = t.size2("farfield", 8192);
    return s;
}

TargetDesc read_target(const TableReader& t, const ReflectorDesc& reflector,
                       const TraceSettings& trace, const std::string& scene_path) {
    t.allow_only({"parameters", "seed", "rays", "file", "absolute"});
    TargetDesc d;
    if (t.has("parameters") == t.has("file"))
        t.fail(nullptr, "", "give either parameters (a target reflector) or file (IES / LDT)");
    if (t.has("file")) {
        d.kind = TargetDesc::Kind::Photometric;
        d.file = t.text("file");
        d.resolved_path = resolve_beside(scene_path, d.file);
        d.absolute = t.boolean_or("absolute", false);
        if (t.has("seed")) t.fail(t.find("seed"), "seed", "only a target reflector has a seed");
        if (t.has("rays")) t.fail(t.find("rays"), "rays", "only a target reflector is traced");
        return d;
    }
    d.kind = TargetDesc::Kind::Reflector;
    const TableReader p = t.sub("parameters");
    for (const auto& [k, v] : p.table()) {
        const std::string name(k.str());
        if (!reflector.parameters.count(name) && !reflector.bspline.groups.count(name))
            p.fail(&v, name, "is not a parameter of the reflector");
        d.parameters[name] = p.number(name);
    }
    d.seed = t.has("seed") ? std::uint64_t(t.integer("seed", 0, INT64_MAX)) : trace.seed + 1;
    if (d.seed == trace.seed)
        t.fail(t.find("seed"), "seed", "must differ from [trace] seed (an independent run)");
    if (t.has("rays")) d.rays = std::uint64_t(t.integer("rays", 1, 10'000'000'000));
    if (t.has("absolute"))
        t.fail(t.find("absolute"), "absolute", "only a photometric target has it");
    return d;
}

OptimizeSettings read_optimize(const TableReader& t) {
    t.allow_only({"method", "metric", "rays", "threshold_lm", "max_evaluations", "smoothness",
                  "height_sampling"});
    OptimizeSettings o;
    if (t.has("height_sampling"))
        o.height_sampling =
            t.choice("height_sampling", {"modes", "independent"}, "modes") == "independent"
                ? HeightSampling::Independent
                : HeightSampling::Modes;
    if (t.has("metric"))
        o.metric = t.choice("metric", {"l2", "candela_l2"}, "l2") == "candela_l2"
                       ? FarFieldMetric::CandelaL2
                       : FarFieldMetric::L2;
    if (t.has("method")) {
        const auto m = method_from_name(t.text("method"));
        if (!m)
            t.fail(t.find("method"), "method",
                   fmt::format("must be one of: {}", fmt::join(method_names(), ", ")));
        o.method = *m;
    }
    if (t.has("rays"))
        for (std::int64_t n : t.integers("rays", 1, 4'000'000'000))
            o.rays.push_back(std::uint64_t(n));
    o.threshold_lm = t.number_or("threshold_lm", 0.0);
    if (o.threshold_lm < 0.0)
        t.fail(t.find("threshold_lm"), "threshold_lm", "must be >= 0 (0: never stop early)");
    if (t.has("max_evaluations"))
        o.max_evaluations = std::uint64_t(t.integer("max_evaluations", 1, 100'000'000));
    o.smoothness = t.number_or("smoothness", 0.0);
    if (o.smoothness < 0.0)
        t.fail(t.find("smoothness"), "smoothness",
               "must be >= 0 (the weight of the bending energy; 0: no penalty)");
    return o;
}

} // namespace

void validate_scene(const Scene& s) {
    const auto fail = [&](const std::string& what) {
        throw SceneError(fmt::format("{}: {}", s.path, what));
    };
    const Holder& h = s.holder;
    if (s.source.center_mm.x < h.min_mm.x || s.source.center_mm.x > h.max_mm.x ||
        s.source.center_mm.y < h.min_mm.y || s.source.center_mm.y > h.max_mm.y)
        fail("[source] center_mm: the light source is outside the holder's xy footprint");
    const auto check = [&](const ReflectorDesc& r, const char* table) {
        try {
            check_reflector_clear_of_source(Surface::make(r, h), s.source);
        } catch (const std::invalid_argument& e) {
            fail(fmt::format("[{}] {}", table, e.what()));
        } catch (const std::runtime_error& e) { // an unreadable mesh file
            fail(fmt::format("[{}] file: {}", table, e.what()));
        }
    };
    check(s.reflector, "reflector");
    if (s.target.kind == TargetDesc::Kind::Reflector) check(target_reflector(s), "target");
}

Scene parse_scene(const std::string& text, const std::string& path) {
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        throw SceneError(fmt::format("{}:{}: {}", path, e.source().begin.line, e.description()));
    }
    const TableReader top(path, root, "");
    top.allow_only(
        {"name", "source", "holder", "reflector", "trace", "target", "optimize", "tolerance"});
    Scene s;
    s.path = path;
    s.name = top.has("name") ? top.text("name") : std::filesystem::path(path).stem().string();
    std::optional<double> subsample;
    s.source = read_source(top.sub("source"), path, subsample);
    if (top.sub("source").has("optimize"))
        s.source_optimize = read_source_optimize(top.sub("source").sub("optimize"), s.source);
    s.holder = read_holder(top.sub("holder"));
    s.reflector = read_reflector(top.sub("reflector"), path);
    std::optional<std::uint64_t> file_rays;
    if (s.source.kind == SourceKind::RayFile)
        file_rays = subsampled_rays(*s.source.ray_file.index, subsample.value_or(1.0));
    s.trace = read_trace(top.sub("trace"), file_rays, subsample.has_value());
    if (top.has("target")) s.target = read_target(top.sub("target"), s.reflector, s.trace, path);
    if (top.has("optimize")) s.optimize = read_optimize(top.sub("optimize"));
    if (s.optimize.smoothness > 0.0 && s.reflector.family == Family::Mesh)
        top.sub("optimize")
            .fail(top.sub("optimize").find("smoothness"), "smoothness",
                  "a mesh's flat facets have no curvature to penalise");
    if (top.has("tolerance")) s.tolerance = read_tolerance(top.sub("tolerance"), s.source);
    validate_scene(s);
    return s;
}

Scene load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SceneError(fmt::format("{}: cannot open the scene file", path));
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_scene(ss.str(), path);
}

namespace {
toml::array vec(const glm::dvec3& v) {
    return toml::array{v.x, v.y, v.z};
}
const char* group_kind(ControlGroup::Kind k) {
    switch (k) {
    case ControlGroup::Kind::Point:
        return "point";
    case ControlGroup::Kind::Row:
        return "row";
    case ControlGroup::Kind::Column:
        return "column";
    case ControlGroup::Kind::Ring:
        return "ring";
    }
    return "point";
}
} // namespace

std::string scene_to_toml(const Scene& s) {
    toml::table source{{"type", source_type_name(s.source.kind)},
                       {"center_mm", vec(s.source.center_mm)},
                       {"flux_lm", s.source.flux_lm}};
    if (s.source.kind == SourceKind::Cylinder) {
        source.insert("axis", vec(s.source.axis));
        source.insert("length_mm", s.source.length_mm);
    }
    if (s.source.kind == SourceKind::Disk || s.source.kind == SourceKind::Rectangle ||
        s.source.kind == SourceKind::Photometric || s.source.kind == SourceKind::RayFile) {
        source.insert("normal", vec(s.source.axis));
        source.insert("x_axis", vec(s.source.x_axis));
    }
    if (s.source.kind == SourceKind::RayFile) {
        source.insert("file", s.source.file); // [trace] rays says how many it emits
    } else if (s.source.kind == SourceKind::Photometric) {
        source.insert("file", s.source.file);
        if (s.source.radius_mm > 0.0) source.insert("radius_mm", s.source.radius_mm);
    } else if (s.source.kind == SourceKind::Rectangle)
        source.insert("size_mm", toml::array{s.source.width_mm, s.source.height_mm});
    else if (s.source.kind != SourceKind::Point)
        source.insert("radius_mm", s.source.radius_mm);
    if (s.source.kind == SourceKind::Point) {
        source.insert("emittance",
                      s.source.emittance == Emittance::Cosine ? "cosine" : "isotropic");
        if (s.source.emittance == Emittance::Cosine) source.insert("axis", vec(s.source.axis));
    }
    if (!s.source_optimize.empty()) {
        toml::table opt;
        for (const auto& [k, r] : s.source_optimize)
            opt.insert(k, toml::table{{"min", r.min}, {"max", r.max}, {"step", r.step}});
        source.insert("optimize", opt);
    }
    toml::table reflector{{"family", family_name(s.reflector.family)}};
    for (const auto& [k, v] : s.reflector.parameters)
        reflector.insert(k, v);
    if (s.reflector.family == Family::BSpline) {
        reflector.insert("grid", toml::array{s.reflector.bspline.nx, s.reflector.bspline.ny});
        toml::array heights;
        for (double h : s.reflector.bspline.heights_mm)
            heights.push_back(h);
        reflector.insert("heights_mm", heights);
        toml::table groups;
        for (const auto& [name, g] : s.reflector.bspline.groups) {
            toml::table gt{{"kind", group_kind(g.kind)}};
            if (g.kind == ControlGroup::Kind::Point) {
                gt.insert("i", g.i);
                gt.insert("j", g.j);
            } else {
                gt.insert("index", g.i);
            }
            groups.insert(name, gt);
        }
        reflector.insert("groups", groups);
    }
    if (s.reflector.family == Family::Profile) { // its h_<k> groups are implicit
        toml::array heights;
        for (double h : s.reflector.bspline.heights_mm)
            heights.push_back(h);
        reflector.insert("heights_mm", heights);
    }
    if (s.reflector.family == Family::Mesh) {
        reflector.insert("file", s.reflector.mesh.file);
        reflector.insert("unit_mm", s.reflector.mesh.unit_mm);
    }
    if (!s.reflector.optimize.empty()) {
        toml::table opt;
        for (const auto& [k, r] : s.reflector.optimize)
            opt.insert(k, toml::table{{"min", r.min}, {"max", r.max}, {"step", r.step}});
        reflector.insert("optimize", opt);
    }
    if (s.reflector.material != MaterialDesc{}) {
        const MaterialDesc& m = s.reflector.material;
        reflector.insert("material",
                         toml::table{{"reflectance", m.reflectance},
                                     {"spread_deg", m.spread_deg},
                                     {"lobe", m.lobe == SpreadLobe::Phong ? "phong" : "gaussian"}});
    }
    if (s.reflector.constraints.any()) {
        const ConstraintsDesc& c = s.reflector.constraints;
        toml::table constraints;
        if (c.max_slope_deg) constraints.insert("max_slope_deg", *c.max_slope_deg);
        if (c.min_radius_mm) constraints.insert("min_radius_mm", *c.min_radius_mm);
        if (c.max_depth_mm) constraints.insert("max_depth_mm", *c.max_depth_mm);
        reflector.insert("constraints", constraints);
    }
    const TraceSettings& t = s.trace;
    toml::table trace{
        {"rays", std::int64_t(t.rays)},
        {"seed", std::int64_t(t.seed)},
        {"max_bounces", std::int64_t(t.max_bounces)},
        {"bounce_policy", t.bounce_policy == BouncePolicy::Strict ? "strict" : "paper"},
        {"sampler", sampler_name(t.sampler)},
        {"hit_mode", t.hit_mode == HitMode::Paper ? "paper" : "refined"},
        {"heightfield", toml::array{std::int64_t(t.heightfield_w), std::int64_t(t.heightfield_h)}},
        {"farfield", toml::array{std::int64_t(t.farfield_w), std::int64_t(t.farfield_h)}}};
    if (t.direct == DirectLight::Include) trace.insert("direct", "include");
    toml::table root{
        {"name", s.name},
        {"source", source},
        {"holder", toml::table{{"min_mm", vec(s.holder.min_mm)}, {"max_mm", vec(s.holder.max_mm)}}},
        {"reflector", reflector},
        {"trace", trace}};
    if (s.target.kind == TargetDesc::Kind::Reflector) {
        toml::table params;
        for (const auto& [k, v] : s.target.parameters)
            params.insert(k, v);
        toml::table target{{"parameters", params}, {"seed", std::int64_t(s.target.seed)}};
        if (s.target.rays) target.insert("rays", std::int64_t(s.target.rays));
        root.insert("target", target);
    } else if (s.target.kind == TargetDesc::Kind::Photometric) {
        root.insert("target",
                    toml::table{{"file", s.target.file}, {"absolute", s.target.absolute}});
    }
    if (s.optimize != OptimizeSettings{}) {
        const OptimizeSettings& o = s.optimize;
        toml::table opt{{"method", method_name(o.method)},
                        {"metric", metric_name(o.metric)},
                        {"threshold_lm", o.threshold_lm},
                        {"max_evaluations", std::int64_t(o.max_evaluations)}};
        if (o.smoothness > 0.0) opt.insert("smoothness", o.smoothness);
        if (o.height_sampling == HeightSampling::Independent)
            opt.insert("height_sampling", "independent");
        if (!o.rays.empty()) {
            toml::array rays;
            for (std::uint64_t n : o.rays)
                rays.push_back(std::int64_t(n));
            opt.insert("rays", rays);
        }
        root.insert("optimize", opt);
    }
    if (s.tolerance != ToleranceDesc{}) {
        const ToleranceDesc& d = s.tolerance;
        root.insert("tolerance", toml::table{{"realisations", std::int64_t(d.realisations)},
                                             {"source_shift_mm", vec(d.source_shift_mm)},
                                             {"source_tilt_deg", d.source_tilt_deg},
                                             {"surface_rms_mm", d.surface_rms_mm},
                                             {"surface_correlation_mm", d.surface_correlation_mm},
                                             {"reflectance_sd", d.reflectance_sd}});
    }
    std::ostringstream out;
    out << root << "\n";
    return out.str();
}

std::string one_line(const std::string& text) {
    std::string line = text;
    for (char& c : line)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
    return line;
}

Scene with_absolute_files(Scene s) {
    namespace fs = std::filesystem;
    if (!s.reflector.mesh.file.empty())
        s.reflector.mesh.file = fs::absolute(s.reflector.mesh.resolved_path).string();
    if (!s.target.file.empty()) s.target.file = fs::absolute(s.target.resolved_path).string();
    if (!s.source.file.empty()) s.source.file = fs::absolute(s.source.resolved_path).string();
    return s;
}

std::string resolve_beside(const std::string& naming_file, const std::string& named) {
    namespace fs = std::filesystem;
    const fs::path p(named);
    if (p.is_absolute()) return p.string();
    return (fs::path(naming_file).parent_path() / p).lexically_normal().string();
}

} // namespace fird
