// The compute worker beside the frame loop: one thread that traces, searches,
// calibrates and traces tolerance realisations through the evaluation seam, on the shared device
// (its own command pool, the queue lock), publishing immutable snapshots the frames show. No frame
// waits on it.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "calibrate/calibration.hpp"
#include "optimize/search.hpp"
#include "photometry/candela_table.hpp"
#include "plot/farfield_picture.hpp"
#include "tolerance/tolerance.hpp"
#include "traced_scene.hpp"

namespace fird::ui {

// One traced state of the scene as the views show it; never changed once published.
struct SceneSnapshot {
    render::TracedScene traced;
    std::map<std::string, double> parameters;
    std::uint64_t rays = 0;
    bool preview = false; // a quick low-ray trace; the full one follows
    std::uint64_t generation = 0;
    // Sums over the far field, taken once by the worker: a frame reads them instead of
    // summing 1.6 million cells again (the zoom's bands, the flux in the panels' text).
    plot::FarFieldProfiles obtained_profiles;
    double obtained_lm = 0.0, desired_lm = 0.0;
    // The candela tables the luminaire views draw (view_table), for their hover readout;
    // none for a far field without light.
    std::optional<CandelaTable> obtained_table, desired_table;
    double view_gamma_deg = 0.0; // luminaire_view_gamma_deg of the two
};

struct SearchProgress {
    bool running = false, paused = false;
    std::string method;
    std::vector<std::string> names;
    std::vector<std::pair<double, double>> bounds; // each parameter's min, max
    std::vector<Candidate> history;
    std::vector<StageSummary> stages;
    std::optional<SearchResult> result; // when finished
    std::string out_dir;                // where its files went
    std::uint64_t generation = 0;
};

struct CalibrationProgress {
    bool running = false;
    std::string kind; // "rays" or "semivariogram"
    std::optional<RaysTable> rays;
    std::optional<SemivariogramResult> semivariogram;
    std::vector<double> partial; // l2 of the runs or points so far
    std::string out_dir;
    std::uint64_t generation = 0;
};

struct ToleranceProgress {
    bool running = false;
    std::vector<RealisationResult> rows;   // traced so far: the nominal one, then the others
    std::size_t total = 0;                 // realisations to trace, the nominal one with them
    std::optional<ToleranceResult> result; // when finished (or stopped)
    std::string scene_name;
    std::string out_dir;
    std::uint64_t generation = 0;
};

// A picked ray re-traced alone, through the reflector of the snapshot it was picked in.
struct PickOutcome {
    std::uint64_t generation = 0; // the snapshot's
    PickedRay ray;
};

struct TraceJob {
    Scene scene;
    std::map<std::string, double> parameters;
    // Progressive: a preview, then the full count; the paths shown and the pick are rays of
    // the full trace's rayset (the last count) in both.
    std::vector<std::uint64_t> rays;
    std::optional<std::uint64_t> pick; // a rayset index
};
// One ray of a traced state, its path and walk (no far field traced again).
struct PickJob {
    std::shared_ptr<const SceneSnapshot> snapshot;
    std::uint64_t index = 0;
};
struct SearchJob {
    Scene scene;
    SearchMethod method = SearchMethod::Auto;
    std::string out_dir;
    bool tailored_start = false; // begin at the profile tailored to the target (search_start.hpp)
};
struct CalibrateJob {
    Scene scene;
    bool rays_table = true;
    std::string parameter; // semivariogram: one parameter, or empty for all
    std::string out_dir;
};
// fird tolerance's realisations of the scene (its [tolerance] table edited in the form).
struct ToleranceJob {
    Scene scene;
    ToleranceDesc tolerances;
    std::uint64_t seed = 1;
    std::string out_dir;
};
using Job = std::variant<TraceJob, PickJob, SearchJob, CalibrateJob, ToleranceJob>;

class Worker {
  public:
    explicit Worker(const vk::Context& ctx);
    ~Worker(); // stops the running job and joins
    Worker(const Worker&) = delete;
    Worker& operator=(const Worker&) = delete;

    // Queues a job; a trace (or a pick) replaces one still waiting (only the latest matters).
    void submit(Job job);
    // Stops the running search or calibration (cleanly: what was done is kept).
    void stop();
    void set_paused(bool paused);
    // Whether a job runs or waits.
    bool busy() const;

    std::shared_ptr<const SceneSnapshot> snapshot() const;
    // The last pick traced on its own (PickJob), if any.
    std::shared_ptr<const PickOutcome> picked() const;
    SearchProgress search() const;
    CalibrationProgress calibration() const;
    ToleranceProgress tolerance() const;
    // Cheap to ask each frame: whether a tolerance job runs or waits (a second is refused),
    // and the generation of its progress (copy tolerance() again only when it moved).
    bool tolerance_pending() const;
    std::uint64_t tolerance_generation() const;
    // Messages since the last call (errors start with "error: ").
    std::vector<std::string> take_log();

    std::uint64_t rays_traced() const { return rays_traced_.load(); }
    std::uint64_t evaluations() const { return evaluations_.load(); }

  private:
    void loop();
    void run(const TraceJob& job);
    void run(const PickJob& job);
    void run(const SearchJob& job);
    void run(const CalibrateJob& job);
    void run(const ToleranceJob& job);
    void publish(render::TracedScene traced, const std::map<std::string, double>& parameters,
                 std::uint64_t rays, bool preview);
    void log(std::string message);

    const vk::Context* ctx_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    std::deque<Job> jobs_;
    bool quit_ = false, running_ = false;
    SearchControl control_;
    std::shared_ptr<const SceneSnapshot> snapshot_;
    std::shared_ptr<const PickOutcome> picked_;
    SearchProgress search_;
    CalibrationProgress calibration_;
    ToleranceProgress tolerance_;
    std::vector<std::string> log_;
    std::uint64_t generation_ = 0;
    std::atomic<std::uint64_t> rays_traced_{0}, evaluations_{0};
    std::thread thread_; // last: starts once everything above exists
};

} // namespace fird::ui
