#include "flat_directions.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace fird {

namespace {

bool has(const std::vector<std::string>& v, const char* name) {
    return std::find(v.begin(), v.end(), name) != v.end();
}

double value(const std::map<std::string, double>& p, const char* name) {
    const auto it = p.find(name);
    return it == p.end() ? 0.0 : it->second;
}

} // namespace

std::vector<FlatDirection> flat_directions(const ReflectorDesc& r,
                                           const std::vector<std::string>& opt) {
    std::vector<FlatDirection> out;
    switch (r.family) {
    case Family::Cup:
        // z = z0 + (h / a^p) |x - cx|^p + (h / b^p) |y - cy|^p: scaling h by s and a, b by
        // s^(1/p) leaves both coefficients, hence the surface, as they are.
        if (has(opt, "a") && has(opt, "b") && has(opt, "h"))
            out.push_back({{"a", "b", "h"}, "h/a^p and h/b^p", "h"});
        break;
    case Family::FlutedCup: {
        // z = z0 + (h / a^p) r^p + (w / a) r cos 8 psi: (s a, s^p h, s w) is the same
        // surface; with the flutes fixed at w = 0, (s a, s^p h) is.
        const bool w_free = has(opt, "w");
        if (has(opt, "a") && has(opt, "h") && (w_free || value(r.parameters, "w") == 0.0))
            out.push_back({w_free ? std::vector<std::string>{"a", "h", "w"}
                                  : std::vector<std::string>{"a", "h"},
                           w_free ? "h/a^p and w/a" : "h/a^p (w = 0)", "h"});
        break;
    }
    case Family::Plane: {
        // z = (z0 - sx cx - sy cy) + sx x + sy y: the offset and a centre trade off.
        for (const char* c : {"cx", "cy"}) {
            const char* slope = c[1] == 'x' ? "sx" : "sy";
            if (has(opt, "z0") && has(opt, c) && (has(opt, slope) || value(r.parameters, slope)))
                out.push_back({{"z0", c}, "z0 - sx cx - sy cy", c});
        }
        if (has(opt, "cx") && has(opt, "cy") && !has(opt, "z0"))
            out.push_back({{"cx", "cy"}, "sx cx + sy cy", "cy"});
        break;
    }
    case Family::Paraboloid:
    case Family::BSpline:
    case Family::Mesh:
    case Family::Profile: // z0 trades with every height alike only when all are free
        break;
    }
    return out;
}

std::optional<std::map<std::string, double>> move_along(const FlatDirection& d, Family family,
                                                        std::map<std::string, double> p,
                                                        double held_value) {
    const double old = value(p, d.held.c_str());
    if (family == Family::Cup || family == Family::FlutedCup) {
        // Along the direction h goes as s^p times a (fluted) or as s times a^p (cup).
        if (!(old > 0.0) || !(held_value > 0.0)) return std::nullopt;
        const double pp = value(p, "p");
        if (!(pp > 0.0)) return std::nullopt;
        const double ratio = held_value / old;
        if (family == Family::Cup) {
            const double scale = std::pow(ratio, 1.0 / pp);
            p["a"] *= scale;
            p["b"] *= scale;
        } else {
            const double scale = std::pow(ratio, 1.0 / pp);
            p["a"] *= scale;
            p["w"] *= scale;
        }
        p["h"] = held_value;
        return p;
    }
    if (family == Family::Plane) {
        // Keep z0 - sx cx - sy cy (or sx cx + sy cy) as it is.
        const bool x = d.held == "cx";
        const double slope = value(p, x ? "sx" : "sy");
        const double moved = held_value - old;
        if (has(d.parameters, "z0")) {
            p["z0"] += slope * moved;
        } else {
            const double other = value(p, "sx");
            if (other == 0.0) return std::nullopt;
            p["cx"] -= slope * moved / other;
        }
        p[d.held] = held_value;
        return p;
    }
    return std::nullopt;
}

std::string describe(const FlatDirection& d) {
    return fmt::format("the surface depends on ({}) only through {}: the search holds {} at its "
                       "start value and lets the others find the shape",
                       fmt::join(d.parameters, ", "), d.invariant, d.held);
}

} // namespace fird
