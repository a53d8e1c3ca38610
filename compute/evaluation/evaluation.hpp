// One lighting evaluation of a scene (DESIGN.md §5 `fird trace`): the reflector's far
// field, the target's (traced with its own seed, or from a photometric file) and l2.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "farfield/farfield.hpp"
#include "model/evaluation_result.hpp"
#include "model/scene.hpp"
#include "reference/reference_tracer.hpp"

namespace fird {

// Scene values that the command line overrides.
struct TraceOverrides {
    std::optional<std::uint64_t> rays;
    std::optional<std::uint64_t> seed;
    std::optional<SamplerKind> sampler;
    unsigned threads = 0;
};

// Applies the overrides (and keeps the target's seed independent of the new seed).
Scene apply_overrides(Scene scene, const TraceOverrides& overrides);

// The CPU reference backend: exact surface, double precision.
Evaluation evaluate_reference(const Scene& scene, unsigned threads = 0);
// The reference tracer's options for the scene's [trace] settings.
ReferenceOptions reference_options(const Scene& scene, unsigned threads = 0);

nlohmann::json evaluation_json(const Evaluation& evaluation);

// The fast path's per-bounce profile (fird trace --profile): rays, device times, walk
// steps and leaf tests per ray, and the lane utilization (steps / lane-steps paid), as
// JSON rows and as a Markdown table.
nlohmann::json profile_json(const std::vector<BounceProfile>& bounces);
std::string profile_table(const std::vector<BounceProfile>& bounces);

// farfield.npy (float32, (H, W), lumens), farfield.png, the luminaire views (polar.png,
// isocandela.png, illuminance.png on a plane `plane_distance_m` below), and with a target
// target.npy / target.png / difference.png (the views then beside the desired ones).
// `producer` names the command in the luminaire files' test label.
void write_evaluation_outputs(const std::string& directory, const Scene& scene,
                              const Evaluation& evaluation,
                              const std::string& producer = "fird trace",
                              double plane_distance_m = 3.0);

// The far field of a photometric [target] (IES / LDT) on the scene's grid, integrated
// over each cell; scaled to `reflector_farfield_lm` unless [target] absolute = true.
// Errors name the scene, the key and the photometric file's line.
FarField photometric_target(const Scene& scene, double reflector_farfield_lm);

} // namespace fird
