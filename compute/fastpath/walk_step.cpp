#include "walk_step.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "fird_shared.h"

namespace fird {

// The shader writes the decisions as fird_shared.h's numbers.
static_assert(std::uint32_t(WalkDecision::Undecided) == gpu::kWalkUndecided &&
              std::uint32_t(WalkDecision::Descend) == gpu::kWalkDescend &&
              std::uint32_t(WalkDecision::Advance) == gpu::kWalkAdvance &&
              std::uint32_t(WalkDecision::Ascend) == gpu::kWalkAscend &&
              std::uint32_t(WalkDecision::Leave) == gpu::kWalkLeave &&
              std::uint32_t(WalkDecision::Hit) == gpu::kWalkHit &&
              std::uint32_t(WalkDecision::NoRoot) == gpu::kWalkNoRoot &&
              std::uint32_t(WalkDecision::OwnTexel) == gpu::kWalkOwnTexel);

const char* walk_decision_name(WalkDecision d) {
    switch (d) {
    case WalkDecision::Undecided:
        return "undecided";
    case WalkDecision::Descend:
        return "descend";
    case WalkDecision::Advance:
        return "advance";
    case WalkDecision::Ascend:
        return "ascend";
    case WalkDecision::Leave:
        return "leave";
    case WalkDecision::Hit:
        return "hit";
    case WalkDecision::NoRoot:
        return "no-root";
    case WalkDecision::OwnTexel:
        return "own-texel";
    }
    return "undecided";
}

std::string walk_step_reason(const WalkStep& s) {
    switch (s.decision) {
    case WalkDecision::Descend:
        return fmt::format("below the node's max: reaches it at t {:.3f}, down to level {}",
                           s.t_next, s.level - 1);
    case WalkDecision::Advance:
        return fmt::format("above the node's max: across its face at t {:.3f}", s.t_next);
    case WalkDecision::Ascend:
        return fmt::format("above the node's max: across its face at t {:.3f} into another "
                           "parent, up to level {}",
                           s.t_next, s.level + 1);
    case WalkDecision::Leave:
        return "above the node's max and out of the holder: no hit";
    case WalkDecision::Hit:
        return fmt::format("the texel's surface is hit at t {:.4f}", s.t_next);
    case WalkDecision::NoRoot:
        return "the texel's surface has no root on the segment: across";
    case WalkDecision::OwnTexel:
        return "the texel the ray reflected from: across";
    case WalkDecision::Undecided:
        break;
    }
    return "the walk stopped here (step limit)";
}

std::string describe_walk_step(const WalkStep& s) {
    return fmt::format("{:<9} b{} L{} node ({}, {})  t {:.3f}..{:.3f} mm  ray z {:.3f}..{:.3f}  "
                       "node max {:.3f}",
                       walk_decision_name(s.decision), s.bounce, s.level, s.x, s.y, s.t, s.t_exit,
                       s.ray_z_mm, s.ray_z_exit_mm, s.max_height_mm);
}

nlohmann::json walk_json(const std::vector<WalkStep>& walk) {
    nlohmann::json steps = nlohmann::json::array();
    for (const WalkStep& s : walk)
        steps.push_back({{"bounce", s.bounce},
                         {"level", s.level},
                         {"node", {s.x, s.y}},
                         {"t_mm", s.t},
                         {"t_exit_mm", s.t_exit},
                         {"ray_z_mm", s.ray_z_mm},
                         {"ray_z_exit_mm", s.ray_z_exit_mm},
                         {"node_max_mm", s.max_height_mm},
                         {"decision", walk_decision_name(s.decision)},
                         {"t_next_mm", s.t_next},
                         {"why", walk_step_reason(s)}});
    return steps;
}

} // namespace fird
