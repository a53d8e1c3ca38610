// The fast path (DESIGN.md §1): rayset, height field and max-mip quadtree, RQRM trace
// with ping-pong over bounces, far-field histogram, on the shared Vulkan device.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "fastpath/mesh_raster.hpp"
#include "fastpath/pass_bindings.hpp"
#include "fastpath/ray_table.hpp"
#include "fastpath/reflector_state.hpp"
#include "fastpath/walk_step.hpp"
#include "fird_shared.h"
#include "model/evaluation_result.hpp"
#include "model/scene.hpp"
#include "model/source.hpp"
#include "passes/reduce_pass.hpp"
#include "vk/buffer.hpp"
#include "vk/timer.hpp"

namespace fird {

struct FastRun {
    RayTally tally;
    std::uint64_t aborted = 0;
    double energy_per_ray_lm = 0.0;
    StageTimings timings; // device time where timestamps exist
    bool rayset_reused = false;
    bool heightfield_reused = false;
    // Per bounce: rays and device times always; steps, lane-steps and leaf tests when
    // profiled (FastTracer::set_profile).
    std::vector<BounceProfile> bounces;
};

// Reflections per texel of the last run (all bounces, and first reflections only), for
// exports and views (FastTracer::set_count_texel_hits).
struct TexelHits {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint32_t> all, first; // row-major, height rows of width texels
};

// One ray's path on the fast path: its origin, each reflection's hit point, and the
// point where it leaves the holder box.
struct RayPath {
    std::uint64_t ray_index = 0; // its index in the rayset (emission order), set by the caller
    std::vector<glm::dvec3> vertices;
    std::uint32_t reflections = 0;
    glm::dvec3 direction{0.0}; // the direction it leaves with
};

// The work the fast path skips when a scene does not need it. Every switch is on in use;
// turning one off is for measuring what it saves (fird bench --skips), never for results.
struct FastPathSkips {
    bool discard_before_trace = true;      // rays that cannot meet the holder are not traced
    bool keep_rayset = true;               // the rayset is kept while only the reflector changes
    bool keep_heightfield = true;          // the height field is kept while the reflector is
    bool skip_empty_bounces = true;        // no workgroup for a bounce without active rays
    bool end_walk_at_reflector_top = true; // a rising ray's walk ends at the highest point
    bool start_walk_below_source = true;   // the source's rays skip the descents they must make
};

// What a bounce loop records besides the far field and the counters (diagnostics).
struct BounceRecording {
    // Hit records (trace.comp's HitRecord): none; the source's rays' (bounce 0, run_rays);
    // or every bounce's (trace_paths: bounce b's from b x `rays`, and the reflected rays
    // left unordered, so that a record's next slot is the next bounce's input slot and a
    // path is followed through the bounces).
    enum class Hits { None, First, Every } hits = Hits::None;
    std::uint32_t rays = 0;                  // Every: the records one bounce takes
    std::optional<std::uint32_t> walk_index; // the walk of the ray carrying this index
};

class FastTracer {
  public:
    // `seed` drives the rayset; scene.trace gives rays, grids, bounces and hit mode.
    // max_batch_rays (0: as the device allows) caps the rays traced per batch.
    FastTracer(const vk::Context& ctx, const Scene& scene, std::uint64_t seed,
               std::uint64_t max_batch_rays = 0);

    // Evaluates the reflector into the height field and quadtree, unless it is the one
    // already there (the rayset is kept either way).
    void set_reflector(const ReflectorDesc& reflector);

    // Draws a fresh rayset from `seed` at the next run (the pipelines, buffers and the
    // height field stay): independent runs of one reflector, as calibration makes them.
    // The source moved or turned (the same kind, size and table): its rays are made again
    // in the next run; the reflectors' height fields are kept.
    void set_source(const SourceDesc& source);
    void set_seed(std::uint64_t seed);

    // Whether run() keeps the rayset for the next run (the default, when it fits the
    // budget). A single evaluation (fird trace) does not: its rays then go straight into
    // a ping-pong buffer, and the memory of a kept copy is never touched.
    void set_rayset_kept(bool kept);

    // Traces every ray of the scene; the far field stays on the device (farfield_lm()).
    // A batch's passes (height field when it changed, rayset when not kept, every bounce
    // with the orderings between them, the histogram) are recorded into one command
    // buffer and waited on once (more rays than one batch: one submission per batch).
    // `then` records more work on the finished far field into the last one (the
    // Evaluator's compare); its device time is timings.compare_ms.
    FastRun run(const std::function<void(VkCommandBuffer)>& then = {});

    // The most candidates run_batch records into one submission.
    static constexpr std::size_t kMaxBatchCandidates = 16;
    // Records `then` for candidate k of a batch, on its far field (farfield_lm).
    using BatchCompare =
        std::function<void(VkCommandBuffer, std::size_t k, const FloatTable& farfield_lm)>;
    // Traces several reflectors against the same rays, each into its own height field and
    // far field, in as few submissions as memory, kMaxBatchCandidates and one batch's rays
    // (candidates x rays per submission) allow: where the kept rayset is one batch, the
    // height fields, bounces, histograms and compares of the candidates are recorded one
    // after another into one command buffer. Each result equals what run() gives
    // for its reflector, count for count. Afterwards the last reflector is the current
    // one (its far field in farfield_lm()). Where one submission cannot hold the work
    // (rays in several batches, a mesh reflector, diagnostics or profiling on), the
    // candidates run one at a time.
    std::vector<FastRun> run_batch(std::span<const ReflectorDesc> reflectors,
                                   const BatchCompare& then = {});

    // Traces given rays (one batch) instead of the source's; hits receives, per input
    // ray, its first hit point (in the scene, out of the device's frame) and t (t < 0: no
    // hit). For comparisons with the reference.
    FastRun run_rays(const std::vector<Ray>& rays, std::vector<glm::dvec4>* hits);

    // For measurement only (see FastPathSkips).
    void set_skips(const FastPathSkips& skips);

    // Count walk steps, the lane-steps the SIMD groups pay and leaf tests per bounce in the
    // next runs (a pipeline variant that counts; off by default).
    void set_profile(bool on);

    // Count reflections per texel in the next runs (off by default: one atomic per hit).
    void set_count_texel_hits(bool on);
    TexelHits read_texel_hits() const;
    // The current height field's max-mip quadtree (the paper's: level 0 is the texel
    // heights; quadtree_layout gives the levels' offsets) and its gradients.
    std::vector<float> read_quadtree();
    std::vector<glm::vec2> read_gradients();
    // The paths of the given rays (at most one batch), traced by the runs' own bounce loop
    // in one submission, each ray's hit recorded at every bounce; the run's far field,
    // tally and texel hits are left as they are (its scratch counts are not). With `walk`, the
    // trace also records ray `pick`'s walk, step by step (a pipeline variant that records; at most
    // kWalkCapacity steps per bounce; its emission index must be no other ray's). The rays'
    // emission indices (the finish's draws are keyed on them: material.h) are `indices` where given
    // (one per ray, below 2^32 as every fast-path rayset's), else first_index, first_index + 1, ...
    std::vector<RayPath> trace_paths(const std::vector<Ray>& rays, std::size_t pick = 0,
                                     std::vector<WalkStep>* walk = nullptr,
                                     std::uint64_t first_index = 0,
                                     const std::vector<std::uint64_t>* indices = nullptr);

    // The rayset of the last run() as traced (ordered by direction), when it was kept
    // (it fits the cache budget); for tests and views of the rays.
    std::vector<Ray> rayset() const;

    const FloatTable& farfield_lm() const { return current_.farfield_lm; }
    // Builds the current reflector's paper quadtree and gradients where they are not (a
    // refined trace of an analytic family reads neither, and builds neither: ReflectorState).
    void build_paper_heightfield();
    // The device height field as the viewport draws it (no readback): the paper quadtree,
    // whose first W x H floats are the texel heights less frame_origin().z, and the
    // gradients (vec2 per texel). Current after build_paper_heightfield() (read_quadtree()
    // and read_gradients() call it) and after a run that traces them (the paper hit mode,
    // or a mesh).
    const vk::Buffer& heights_buffer() const { return current_.paper_tree; }
    const vk::Buffer& gradients_buffer() const { return current_.gradients; }
    // Where the device's frame sits in the scene (the holder's centre, scene_params.hpp).
    const glm::dvec3& frame_origin() const { return origin_; }
    std::uint32_t heightfield_width() const { return params_.hf_w; }
    std::uint32_t heightfield_height() const { return params_.hf_h; }
    std::vector<double> read_farfield() const;
    std::uint32_t farfield_cells() const { return params_.ff_w * params_.ff_h; }

  private:
    // A trace pass over the rays in `in`: `groups` workgroups for the count in loop_, or
    // (none) as many as the bounce loop's state asks for (an indirect dispatch).
    void dispatch_trace(VkCommandBuffer cb, const RayTable& in, const RayTable& out,
                        const vk::Buffer& counters, const vk::Buffer& farfield,
                        const gpu::TracePush& push, bool record_walk,
                        std::optional<std::uint32_t> groups);
    // Records, submits and waits once, then adds each timed pass's device time where it
    // belongs. Where the device has no timestamps the submission's wall time goes to
    // *untimed_ms.
    void submit(double* untimed_ms, const std::function<void(VkCommandBuffer)>& record);
    // Records `record` between a timestamp pair whose time is added to *stage_ms and, when
    // given, to *bounce_ms (pointers into the run, stable while it records).
    void timed(VkCommandBuffer cb, double* stage_ms, double* bounce_ms,
               const std::function<void()>& record);
    // The mesh reflector's raster (its own submissions, once per mesh: the texel centres'
    // grid and the corners') when the height field changed; returns its wall time.
    double rasterize_mesh();
    // The height field, quadtree and walk start when the reflector changed: what the trace
    // reads, and with `with_paper` also the paper's products where the trace does not.
    void record_heightfield(VkCommandBuffer cb, FastRun& run, bool with_paper = false);
    // Whether the trace reads the paper quadtree and the texel gradients.
    bool trace_reads_paper_tree() const;
    // Clears the far field (and the diagnostics' counts) for a run.
    void record_run_start(VkCommandBuffer cb, bool clear_diagnostics);
    // Clears a batch's counters and the bounce loop's state; `effective` (rays given, not
    // generated) is set as the rayset pass would count it.
    void record_batch_start(VkCommandBuffer cb, std::optional<std::uint64_t> effective,
                            std::uint64_t emitted);
    // The rayset pass over rays [first, first + n): appends the effective ones to `rays`
    // (and counts them per direction bucket unless they come ordered).
    void record_rayset(VkCommandBuffer cb, std::uint64_t first, std::uint64_t n,
                       const RayTable& rays, FastRun& run);
    // A ray file source: reads emissions [first, first + n) into the batch's table
    // (ray_file_table), placed in the fast path's frame. Touches no other state, so the next
    // batch is read on a host thread while the device traces this one.
    void read_ray_file_batch(std::uint64_t first, std::uint64_t n) const;
    // What the rayset pass over rays [first, ...) reads: a photometric source's table, or
    // the ray file table of that batch (two, used in turn: double-buffered).
    const FloatTable& emitter_table_for(std::uint64_t first) const;
    // Moves the rayset's effective rays from `from` to `to` ordered by direction.
    void record_rayset_order(VkCommandBuffer cb, const RayTable& from, const RayTable& to,
                             FastRun& run);
    void record_bounce_args(VkCommandBuffer cb, std::uint32_t stage, std::uint32_t bounce);
    // bucket_scan.comp and rayset_order.comp, their counts and mode from loop_.
    void record_order(VkCommandBuffer cb, const RayTable& from, const RayTable& to, bool reflected);
    // Every bounce of a batch whose rays are in `rays` (their count in the counters'
    // kCounterEffective): the trace, and between bounces the ordering of the rays it
    // reflected, sized on the device.
    // `first`: the emission index of the batch's first ray (the rays carry their index's
    // low word: TracePush).
    void record_bounces(VkCommandBuffer cb, const RayTable& rays, std::uint64_t first, FastRun& run,
                        const BounceRecording& recording = {});
    void record_to_lm(VkCommandBuffer cb, FastRun& run);
    // The batch's readback, one small copy each: the counters and the loop's per-bounce
    // counts, for the host, into readback slot `slot` (a candidate's place in a run_batch
    // submission; 0 for run()).
    void record_batch_end(VkCommandBuffer cb, std::size_t slot = 0);
    // Adds the batch's counters and per-bounce rays of readback slot `slot` (read back
    // once, after its wait).
    void tally_batch(FastRun& run, std::size_t slot = 0) const;
    // run_batch's one submission for reflectors already set into batch_states_[0, n - 1)
    // and current_ (the last): the kept single-batch rayset traced against each.
    // `first`: the first candidate's index in run_batch's list (then's k).
    void run_batch_submission(std::span<FastRun> runs, const BatchCompare& then, std::size_t first);
    // A run's tally and bounces, empty, for `emitted` rays.
    FastRun new_run(std::uint64_t emitted) const;
    // Refuses a reflector of another family than the pipelines were built for.
    void require_family(const ReflectorDesc& reflector) const;
    // The reflector state being recorded: current_, or batch_states_[recording_ - 1].
    ReflectorState& state();
    const ReflectorState& state() const;
    // The bounces that traced rays (all of them where empty ones are not skipped); checks
    // the energy balance.
    void finish(FastRun& run) const;
    bool rayset_ordered_at_birth() const {
        return gpu::rayset_ordered_at_birth(params_.sampler_kind, params_.source_kind);
    }
    std::uint32_t passes() const { return params_.max_bounces + (params_.strict_policy ? 1u : 0u); }
    void read_profile(FastRun& run) const; // the profiling pipeline's counts, per bounce

    const vk::Context* ctx_;
    Scene scene_;
    glm::dvec3 origin_;         // the device's frame (frame_origin): device positions are relative
    gpu::SceneParams params_{}; // the scene's (every reflector state adds its own family's)
    ReflectorState current_;    // the current reflector's height field and far field
    // A batch's other candidates (run_batch), kept for the next batch; recording_ says
    // which state the passes being recorded use (0: current_, k: batch_states_[k - 1]).
    std::vector<ReflectorState> batch_states_;
    std::size_t recording_ = 0;
    std::size_t batch_states_cap_ = kMaxBatchCandidates; // lowered by an out-of-memory
    std::uint64_t batch_capacity_ = 0;
    std::uint64_t submission_rays_ = 0; // the most rays one submission traces (a batch's cap)
    // One batch's effective rays, ordered by direction, kept for the next run.
    struct RaysetChunk {
        RayTable rays;
        std::uint64_t effective = 0;
    };
    bool rayset_fits_ = false;               // the whole rayset fits the cache budget
    bool cache_rayset_ = false;              // ... and is kept between runs
    std::vector<RaysetChunk> rayset_chunks_; // batch i's kept rays at [i]
    bool count_texel_hits_ = false;
    FastPathSkips skips_;

    std::array<std::uint32_t, FIRD_SPEC_COUNT> spec_; // the scene's fixed shader choices
    passes::RaysetPass rayset_pipeline_;
    passes::HeightfieldPass heightfield_pipeline_;
    passes::HeightfieldPass heightfield_refined_pipeline_; // FIRD_SPEC_REFINED_ONLY 1
    passes::MaxMipPass maxmip_level0_pipeline_;            // FIRD_SPEC_MAXMIP_LEVEL_ZERO 1
    passes::MaxMipPass maxmip_pipeline_;                   // the levels above
    passes::MaxMipPass maxmip_refined_pipeline_;           // ... the refined pyramid's alone
    // [0] bounce 0's, [1] the bounces after's (FIRD_SPEC_BOUNCE_KIND).
    std::array<passes::TracePass, 2> trace_pipelines_;
    passes::ToLmPass to_lm_pipeline_;
    passes::OrderPass order_pipeline_;
    passes::BucketScanPass bucket_scan_pipeline_;
    passes::WalkStartPass walk_start_pipeline_;
    passes::BounceArgsPass bounce_args_pipeline_;
    vk::Buffer counters_, hits_, texel_hits_, walk_;
    RayTable rays_ping_, rays_pong_;
    std::optional<passes::TracePass> trace_walk_pipeline_;    // built when a walk is asked for
    std::optional<passes::TracePass> trace_profile_pipeline_; // built when profiling
    // Built when hits are recorded or texel hits counted.
    std::optional<passes::TracePass> trace_diagnostics_pipeline_;
    vk::Buffer profile_;
    vk::Buffer order_buckets_;
    // A photometric source's table (fird_shared.h); one unused float for the others.
    FloatTable emitter_table_;
    // A ray file's rays, for even and odd batches: one is read while the other is traced.
    FloatTable ray_file_tables_[2];
    // The bounce loop's state on the device (fird_shared.h, kLoop*: counts and indirect
    // dispatch sizes) and its per-bounce counts as read back.
    vk::Buffer loop_, loop_readback_;
    // The counters as read back: the tally's and the append allocator's atomics stay in
    // device-local memory (counters_), copied here at the end of each batch's submission.
    vk::Buffer counters_readback_;
    vk::GpuTimer timer_;
    struct TimedPass {
        std::uint32_t pair;
        double* stage_ms;
        double* bounce_ms;
    };
    std::vector<TimedPass> timed_;                  // the passes of the recording in progress
    std::optional<MeshRasterizer> mesh_rasterizer_; // mesh reflectors only
    std::optional<TriangleMesh> mesh_;              // the reflector's, loaded once per file
};

// l2 between two far fields on the device (reduction; only the number is read back).
// With a weighted difference (ReduceDifference), that metric's distance.
double device_l2(const vk::Context& ctx, const ReducePass& reduce, const FloatTable& a,
                 const FloatTable& b, std::uint32_t cells, double* compare_ms = nullptr,
                 ReduceDifference difference = {});

} // namespace fird
