// Tolerance analysis (fird tolerance, issue 27 item 4): how much the light moves when the
// part is made a little wrong or the light source sits a little off. Each realisation draws
// its errors (normal, of the given standard deviations) from the counter-based generator on
// (seed, realisation), makes the perturbed scene and traces it as an independent
// evaluation; the joint run draws every error, and one run per tolerance draws that one
// alone (one-at-a-time sensitivities, the same draws as the joint run's).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "evaluation/evaluator.hpp"
#include "model/scene.hpp"
#include "plot/chart.hpp"
#include "vk/context.hpp"

namespace fird {

// One realisation's errors.
struct ToleranceDraw {
    glm::dvec3 source_shift_mm{0.0};
    double tilt_x_deg = 0.0, tilt_y_deg = 0.0;
    double reflectance = 1.0; // the drawn reflectance (clamped to [0, 1])
    bool surface = false;     // a surface error of its own
};

// The errors of realisation r (every tolerance of `tol`; `only` keeps one: "source_shift",
// "source_tilt", "surface", "reflectance").
ToleranceDraw draw_tolerances(const ToleranceDesc& tol, const Scene& scene, std::uint64_t seed,
                              std::uint64_t realisation, const std::string& only = "");

// The names of the tolerances `tol` gives (non-zero), in a fixed order.
std::vector<std::string> active_tolerances(const ToleranceDesc& tol);

struct RealisationResult {
    std::string kind; // "nominal", "joint" or a tolerance's name
    std::uint64_t realisation = 0;
    ToleranceDraw draw;
    double surface_rms_mm = 0.0; // the drawn surface error's RMS over the mesh
    std::optional<double> l2_lm; // with a target
    double efficiency = 0.0;     // what the far field holds over the source's flux
    double peak_cd = 0.0;
    double beam_angle_deg = 0.0;
    // The realisation's source stays over the footprint and clear of the surface (the
    // search's check): else it is traced and listed, but left out of the spreads.
    bool feasible = true;
};

struct Spread {
    double median = 0.0, p5 = 0.0, p95 = 0.0;
};
// Median, 5 % and 95 % (linear between order statistics).
Spread spread_of(std::vector<double> values);

struct ToleranceResult {
    ToleranceDesc tolerances;
    std::uint64_t seed = 0;
    RealisationResult nominal;
    std::vector<RealisationResult> rows; // joint, then each tolerance's
    std::vector<std::string> active;
    std::string most_sensitive; // the tolerance whose own runs spread the metric most
    std::string ranked_by;      // "l2" (with a target) or "efficiency"
    FarFieldMetric metric = FarFieldMetric::L2; // what each l2 measures (the scene's)
    std::uint64_t infeasible = 0; // rows left out of the spreads (ToleranceResult::rows)
    // Stopped before every realisation was traced (ToleranceRun::stop): the spreads are of
    // the rows traced, the joint run's first.
    bool stopped = false;
    double time_s = 0.0;
};

// A realisation to trace after the nominal one: its kind ("joint" or a tolerance's name)
// and number; its draws follow from them and the run's seed.
struct RealisationKey {
    std::string kind;
    std::uint64_t realisation = 0;
};
using RealisationTracer =
    std::function<std::vector<RealisationResult>(std::span<const RealisationKey>)>;

// Traces the realisations across processes (fird tolerance under mpirun:
// compute/distributed): given them, the desired far field (null: none) and `here`, which
// traces a share in this process; answers their rows in order, whichever process traced
// them. Empty: all traced here.
struct DistributedRealisations {
    std::size_t processes = 1;
    std::function<std::vector<RealisationResult>(
        std::span<const RealisationKey>, const FarField* desired, const RealisationTracer& here)>
        trace;
};

struct ToleranceRun {
    ToleranceDesc tolerances;
    std::uint64_t seed = 1;
    Backend backend = Backend::Fast;
    std::string scratch_dir; // perturbed meshes are written (and removed) here
    // Called after each realisation (progress).
    std::function<void(const RealisationResult&, std::size_t done, std::size_t total)> progress;
    DistributedRealisations distributed;
    // Set by another thread (the workbench's Stop): no realisation is begun after it.
    const std::atomic<bool>* stop = nullptr;
};

// Realisations of `run` traced in this process against `desired` (null: no target), each as
// run_tolerance traces it (a perturbed mesh written to, and removed from, the scratch folder).
std::vector<RealisationResult> trace_realisations(const vk::Context& ctx, const Scene& scene,
                                                  const ToleranceRun& run,
                                                  std::span<const RealisationKey> keys,
                                                  const FarField* desired);

ToleranceResult run_tolerance(const vk::Context& ctx, const Scene& scene, const ToleranceRun& run);

nlohmann::json tolerance_json(const ToleranceResult& r);
// tolerance.png's chart: each run's metric (l2 with a target, else efficiency) over its
// realisations, sorted (a distribution per tolerance), the nominal value marked.
plot::Chart tolerance_chart(const std::string& scene_name, const ToleranceResult& r);
// tolerance.csv (one row per realisation), tolerance.json and tolerance.png, whole or not
// at all.
void write_tolerance_outputs(const std::string& dir, const Scene& scene, const ToleranceResult& r);

} // namespace fird
