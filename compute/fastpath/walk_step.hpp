// One step of a ray's RQRM walk as the trace recorded it, named as the paper's Algorithms
// 2-4 name them (quadtree level, node, the ray parameter t, the node's max height and the
// ray's height there, and the decision taken), with its description in words and JSON.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace fird {

// What a step decided (fird_shared.h kWalk*: the values are the shader's).
enum class WalkDecision : std::uint32_t {
    Undecided = 0, // the walk stopped at this step (its step limit)
    Descend = 1,   // the ray reaches the node's max height inside it: down a level
    Advance = 2,   // the ray stays above the node: on to the neighbour in the same parent
    Ascend = 3,    // ... the neighbour lies in another parent: across, then up a level
    Leave = 4,     // the ray leaves the holder (or rises past the reflector's top): no hit
    Hit = 5,       // a texel's leaf test found the surface: the root is t_next
    NoRoot = 6,    // a texel's leaf test found no root: across the texel
    OwnTexel = 7,  // the texel a reflected ray starts from (never hit again): across it
};

// The step's decision as a JSON value and in the walk list ("descend", "hit", ...).
const char* walk_decision_name(WalkDecision d);

struct WalkStep {
    std::uint32_t bounce = 0;   // reflections before it
    std::uint32_t level = 0;    // quadtree level (0: a texel)
    std::uint32_t x = 0, y = 0; // the node (i, j) at that level
    float max_height_mm = 0.0f; // the node's max height (scene z)
    // Along the ray of this bounce (mm from its origin: the source, or the last hit).
    float t = 0.0f, t_exit = 0.0f;               // where it is, where it leaves the node
    float ray_z_mm = 0.0f, ray_z_exit_mm = 0.0f; // its height at t and at t_exit (scene z)
    WalkDecision decision = WalkDecision::Undecided;
    float t_next = 0.0f; // where the decision moves it: the descent's t, the face, the root
};

// One line, the decision first: "descend   b0 L3 node (28, 17)  t 8.326..8.721 mm  ray z
// -0.640..-0.907  node max -0.800".
std::string describe_walk_step(const WalkStep& step);
// Why the step decided as it did, in the terms of the comparison that made it: "below the
// node's max: reaches it at t 8.562, down to level 2".
std::string walk_step_reason(const WalkStep& step);

// {"bounce", "level", "node": [i, j], "t_mm", "t_exit_mm", "ray_z_mm", "ray_z_exit_mm",
//  "node_max_mm", "decision", "t_next_mm", "why"} per step (docs/workbench.md).
nlohmann::json walk_json(const std::vector<WalkStep>& walk);

} // namespace fird
