// The evaluation seam: one object that owns, for one scene at one fidelity, the fast
// tracer and its rayset (common random numbers: the same seeded rays for every candidate),
// the desired far field on the device and the reduction, and answers l2 for a reflector
// reading back only numbers. `fird trace`, `fird bench`, the optimizer, calibration,
// export and the workbench all evaluate through it.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "farfield/farfield.hpp"
#include "fastpath/fast_tracer.hpp"
#include "fastpath/picked_ray.hpp"
#include "model/evaluation_result.hpp"
#include "model/scene.hpp"
#include "passes/reduce_pass.hpp"
#include "vk/buffer.hpp"

namespace fird {

// How finely one evaluation looks: its rays (and their seed), the far-field grid it bins
// into and the height field it traces against. A search's early stages look coarsely.
struct Fidelity {
    std::uint64_t rays = 0;
    std::uint64_t seed = 1;
    std::uint32_t farfield_w = 0, farfield_h = 0;
    std::uint32_t heightfield_w = 0, heightfield_h = 0;
    bool operator==(const Fidelity&) const = default;
};

// The scene's own fidelity ([trace] rays, seed and grids).
Fidelity scene_fidelity(const Scene& scene);
// The scene as traced at `fidelity`.
Scene at_fidelity(Scene scene, const Fidelity& fidelity);

struct CandidateResult {
    FastRun run;                 // tally and per-stage device times
    std::optional<double> l2_lm; // when a desired far field is set
    double farfield_lm = 0.0;    // light the far field holds (EnergyBalance::binned_lm)
    double wall_ms = 0.0;        // the whole evaluation, as the caller waits for it
    // Its far field, read back when asked for (evaluate_batch's read_farfields): for
    // methods that model the far field itself, not only its distance.
    std::optional<FarField> farfield;
};

// Which tracer answers: the fast path on the device, or the CPU reference (exact surface,
// double precision: the same source sampling, rays and far-field binning, seconds where
// the fast path takes milliseconds; for checking a search by another tracer).
enum class Backend { Fast, Reference };
const char* backend_name(Backend backend); // "gpu", "cpu" (fird trace --backend)

class Evaluator {
  public:
    Evaluator(const vk::Context& ctx, const Scene& scene, const Fidelity& fidelity,
              Backend backend = Backend::Fast);

    // The desired far field, on the scene's grid or on this fidelity's (coarsened to it
    // when finer). Uploaded once; every later evaluate() compares against it.
    void set_desired(const FarField& desired);
    bool has_desired() const { return desired_norm_lm_.has_value(); }
    // ||desired||: the l2 of a reflector that sends no light at all.
    double desired_norm_lm() const { return desired_norm_lm_.value_or(0.0); }

    // Traces the reflector (the height field is rebuilt only when it changed; the
    // rayset is kept) and, with a desired far field, reduces l2 on the device in the same
    // submission as the trace's last batch (one wait per evaluation).
    CandidateResult evaluate(const ReflectorDesc& reflector);
    // Several candidates against the same rays, as few submissions as the device allows
    // (FastTracer::run_batch): each result equals evaluate()'s for its reflector, count for
    // count; wall_ms is its share of the batch's. The last one's far field is farfield().
    // With `read_farfields`, each result holds its far field too (copied out in the same
    // submission: one readback for the batch).
    std::vector<CandidateResult> evaluate_batch(std::span<const ReflectorDesc> reflectors,
                                                bool read_farfields = false);
    // Fresh rays from `seed` for the next evaluations (nothing else is rebuilt).
    void set_seed(std::uint64_t seed);
    // The source moved or turned ([source.optimize]: the same kind and size): the next
    // evaluations trace its rays (the rayset is made again; the height field is kept).
    void set_source(const SourceDesc& source);

    // l2 of the last traced far field to the desired one (needs both).
    double compare(double* compare_ms = nullptr) const;

    // l2 between this evaluator's last far field and another's of the same grid (e.g.
    // two independent traces of one reflector: the noise floor), reduced on the device.
    double l2_to(const Evaluator& other) const;

    // The last traced far field, read back (for pictures and files, not per candidate).
    FarField farfield() const;
    // The fast path's far field on the device (the fast backend only).
    const vk::Buffer& farfield_buffer() const { return fast().farfield_lm().values; }
    std::uint32_t cells() const { return fidelity_.farfield_w * fidelity_.farfield_h; }
    // What compare(), l2_to() and every CandidateResult::l2_lm measure: the scene's
    // [optimize] metric (l2 in lm, or candela_l2 in cd).
    FarFieldMetric metric() const { return scene_.optimize.metric; }
    const Fidelity& fidelity() const { return fidelity_; }
    const Scene& scene() const { return scene_; }
    Backend backend() const { return backend_; }

    // What each skip of the fast path saves is measured by switching it off (fird bench
    // --skips, --candidates); never for results. The fast backend only, as below.
    void set_skips(const FastPathSkips& skips) { fast().set_skips(skips); }
    // Walk steps, lane-steps and leaf tests per bounce in the next evaluations (fird trace
    // --profile); whether the rayset is kept for the next (one evaluation: not).
    void set_profile(bool on) { fast().set_profile(on); }
    void set_rayset_kept(bool kept) { fast().set_rayset_kept(kept); }

    // Views and diagnostics of the fast path (the viewport, fird export, ray picking): the
    // height field as the device traces it, without a readback, and read back; reflections
    // counted per texel in the next evaluations; given rays' paths (the bounce loop's own).
    struct DeviceHeightField {
        const vk::Buffer* heights = nullptr;   // the paper quadtree (FastTracer::heights_buffer)
        const vk::Buffer* gradients = nullptr; // vec2 per texel
        double origin_z_mm = 0.0;              // the device frame's z (heights are relative)
        std::uint32_t width = 0, height = 0;
    };
    DeviceHeightField device_heightfield();
    std::vector<float> read_quadtree() { return fast().read_quadtree(); }
    std::vector<glm::vec2> read_gradients() { return fast().read_gradients(); }
    void set_count_texel_hits(bool on) { fast().set_count_texel_hits(on); }
    TexelHits read_texel_hits() const { return fast().read_texel_hits(); }
    // `indices`: the rays' emission indices (their finish's draws), else 0, 1, ...
    std::vector<RayPath> trace_paths(const std::vector<Ray>& rays,
                                     const std::vector<std::uint64_t>* indices = nullptr) {
        return fast().trace_paths(rays, 0, nullptr, 0, indices);
    }
    // Ray `index` of `scene`'s rayset, its path and its walk (picked_ray.hpp).
    PickedRay pick_ray(const Scene& scene, std::uint64_t index) {
        return trace_picked_ray(fast(), scene, index);
    }

  private:
    ReduceDifference difference() const {
        return {metric(), fidelity_.farfield_w,
                row_weights_.values.get() ? &row_weights_ : nullptr};
    }
    FastTracer& fast();
    const FastTracer& fast() const;
    // The reference backend's evaluation of one candidate (its far field kept).
    CandidateResult evaluate_on_cpu(const ReflectorDesc& reflector);

    const vk::Context* ctx_;
    Fidelity fidelity_;
    Scene scene_; // at the fidelity
    Backend backend_;
    std::optional<FastTracer> tracer_;                   // the fast backend
    std::optional<FarField> cpu_farfield_, cpu_desired_; // the reference backend's last and desired
    ReducePass reduce_;
    FloatTable desired_;
    // evaluate()'s reduction: its levels, and the sums read back (one per candidate of a
    // batch, kL2SumStride bytes apart: storage-buffer offsets are aligned).
    FloatTable l2_scratch_;
    vk::Buffer l2_sums_;
    vk::Buffer farfields_readback_; // evaluate_batch's far fields, when read back
    FloatTable row_weights_;        // the metric's weight per far-field row (weighted metrics)
    static constexpr VkDeviceSize kL2SumStride = 256;
    std::optional<double> desired_norm_lm_;
    bool traced_ = false;
};

// One evaluation of the scene as `fird trace` runs it on the fast path: its reflector at
// the scene's fidelity and, with a [target], the desired far field and l2 (a relative
// photometric target scaled to this reflector's far-field flux).
// What `fird trace` asks of one fast evaluation beyond the numbers.
struct FastEvaluationOptions {
    // The trace runs its counting variant; the result holds the bounces' walk steps,
    // lane-steps and leaf tests (fird trace --profile).
    bool profile = false;
    // Read the far fields back into the result (pictures and files need them; the JSON
    // numbers do not: the tally and l2 come from the device).
    bool read_farfields = true;
};
Evaluation evaluate_fast(const vk::Context& ctx, const Scene& scene,
                         const FastEvaluationOptions& options = {});

} // namespace fird
