// Directions in parameter space along which a family's surface does not change at all,
// so a search must not wander along them (docs/optimization.md, "Degrees of freedom").
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "model/scene.hpp"

namespace fird {

struct FlatDirection {
    std::vector<std::string> parameters; // the optimized parameters that move along it
    std::string invariant;               // what fixes the surface, e.g. "h/a^p and h/b^p"
    std::string held;                    // the parameter adaptive searches hold fixed
};

// The flat directions among the optimized parameters `optimized` of the reflector
// (cup: for fixed p only h/a^p and h/b^p shape the surface; fluted cup: h/a^p and w/a;
// plane: z0 - sx cx - sy cy).
std::vector<FlatDirection> flat_directions(const ReflectorDesc& reflector,
                                           const std::vector<std::string>& optimized);

// The parameters with `direction.held` set to `held_value` and the others moved along the
// direction so that the surface is unchanged; nullopt where no such point exists.
std::optional<std::map<std::string, double>> move_along(const FlatDirection& direction,
                                                        Family family,
                                                        std::map<std::string, double> parameters,
                                                        double held_value);

std::string describe(const FlatDirection& direction);

} // namespace fird
