#include "worker.hpp"

#include <chrono>
#include <filesystem>

#include <fmt/format.h>

#include "calibrate/calibration_report.hpp"
#include "export/export_modules.hpp"
#include "io/atomic_file.hpp"
#include "optimize/history_csv.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search_report.hpp"
#include "optimize/search_start.hpp"
#include "photometry/luminaire_pictures.hpp"

namespace fird::ui {

namespace {
// Rays of a view traced while a search runs (the current best, shown in the viewport).
constexpr std::uint64_t kBestViewRays = 100000;
constexpr double kBestViewEvery_s = 2.0;
} // namespace

Worker::Worker(const vk::Context& ctx) : ctx_(&ctx), thread_([this] { loop(); }) {}

Worker::~Worker() {
    {
        const std::lock_guard lock(mutex_);
        quit_ = true;
        jobs_.clear();
    }
    control_.stop = true;
    wake_.notify_all();
    thread_.join();
}

void Worker::submit(Job job) {
    {
        const std::lock_guard lock(mutex_);
        const std::size_t kind = job.index();
        if (std::holds_alternative<TraceJob>(job) || std::holds_alternative<PickJob>(job))
            std::erase_if(jobs_, [&](const Job& j) { return j.index() == kind; });
        jobs_.push_back(std::move(job));
    }
    wake_.notify_all();
}

void Worker::stop() {
    control_.stop = true;
    control_.pause = false;
}

void Worker::set_paused(bool paused) {
    control_.pause = paused;
    const std::lock_guard lock(mutex_);
    search_.paused = paused;
}

bool Worker::busy() const {
    const std::lock_guard lock(mutex_);
    return running_ || !jobs_.empty();
}

std::shared_ptr<const SceneSnapshot> Worker::snapshot() const {
    const std::lock_guard lock(mutex_);
    return snapshot_;
}

std::shared_ptr<const PickOutcome> Worker::picked() const {
    const std::lock_guard lock(mutex_);
    return picked_;
}

SearchProgress Worker::search() const {
    const std::lock_guard lock(mutex_);
    return search_;
}

CalibrationProgress Worker::calibration() const {
    const std::lock_guard lock(mutex_);
    return calibration_;
}

ToleranceProgress Worker::tolerance() const {
    const std::lock_guard lock(mutex_);
    return tolerance_;
}

bool Worker::tolerance_pending() const {
    const std::lock_guard lock(mutex_);
    return tolerance_.running || std::any_of(jobs_.begin(), jobs_.end(), [](const Job& j) {
               return std::holds_alternative<ToleranceJob>(j);
           });
}

std::uint64_t Worker::tolerance_generation() const {
    const std::lock_guard lock(mutex_);
    return tolerance_.generation;
}

std::vector<std::string> Worker::take_log() {
    const std::lock_guard lock(mutex_);
    return std::exchange(log_, {});
}

void Worker::log(std::string message) {
    const std::lock_guard lock(mutex_);
    log_.push_back(std::move(message));
}

void Worker::loop() {
    for (;;) {
        Job job;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return quit_ || !jobs_.empty(); });
            if (quit_) return;
            job = std::move(jobs_.front());
            jobs_.pop_front();
            running_ = true;
        }
        control_.stop = false;
        try {
            std::visit([&](const auto& j) { run(j); }, job);
        } catch (const std::exception& e) {
            log(std::string("error: ") + e.what());
        }
        const std::lock_guard lock(mutex_);
        running_ = false;
        // A job that failed ends its progress too: the panel that copies a tolerance run's
        // progress only when it moves must see it end.
        if (std::holds_alternative<ToleranceJob>(job) && tolerance_.running)
            ++tolerance_.generation;
        search_.running = calibration_.running = tolerance_.running = false;
    }
}

void Worker::publish(render::TracedScene traced, const std::map<std::string, double>& parameters,
                     std::uint64_t rays, bool preview) {
    auto s = std::make_shared<SceneSnapshot>();
    s->traced = std::move(traced);
    s->parameters = parameters;
    s->rays = rays;
    s->preview = preview;
    const auto& ff = s->traced.farfield;
    s->obtained_profiles = plot::light_profiles(ff.obtained);
    s->obtained_lm = ff.obtained.total_lm();
    s->desired_lm = ff.desired ? ff.desired->total_lm() : 0.0;
    // As draw_farfield_view takes them (a far field with light only).
    if (s->obtained_lm > 0.0) s->obtained_table = view_table(ff.obtained);
    if (s->desired_lm > 0.0) s->desired_table = view_table(*ff.desired);
    if (s->obtained_table)
        s->view_gamma_deg = luminaire_view_gamma_deg(
            *s->obtained_table, s->desired_table ? &*s->desired_table : nullptr);
    const std::lock_guard lock(mutex_);
    s->generation = ++generation_;
    snapshot_ = std::move(s);
}

void Worker::run(const TraceJob& job) {
    for (std::size_t k = 0; k < job.rays.size(); ++k) {
        {
            // A newer trace waiting makes this one moot.
            const std::lock_guard lock(mutex_);
            if (quit_ || std::any_of(jobs_.begin(), jobs_.end(), [](const Job& j) {
                    return std::holds_alternative<TraceJob>(j);
                }))
                return;
        }
        render::TracedScene t = render::trace_for_views(
            *ctx_, job.scene,
            {.parameters = job.parameters, .rays = job.rays[k], .rayset_rays = job.rays.back()});
        if (job.pick) {
            // A pick that fails (a rayset changed under it) is logged; the trace stands.
            try {
                t.viewport.picked = render::pick_ray(t, *job.pick);
            } catch (const std::invalid_argument& e) {
                log(std::string("error: pick: ") + e.what());
            }
        }
        rays_traced_ += job.rays[k];
        ++evaluations_;
        publish(std::move(t), job.parameters, job.rays[k], k + 1 < job.rays.size());
    }
}

void Worker::run(const PickJob& job) {
    {
        const std::lock_guard lock(mutex_);
        if (job.snapshot != snapshot_) return; // a newer trace came: the panel asks again
    }
    auto outcome = std::make_shared<PickOutcome>(
        PickOutcome{job.snapshot->generation, render::pick_ray(job.snapshot->traced, job.index)});
    const std::lock_guard lock(mutex_);
    picked_ = std::move(outcome);
}

void Worker::run(const SearchJob& job) {
    const ParameterSpace space = parameter_space(job.scene);
    // The VTK module for the folder's reflectors.pvd, before the search (a missing one is
    // this job's error now, not after the search).
    const auto export_search_reflectors =
        job.out_dir.empty() ? nullptr : vtk_exports().search_reflectors;
    {
        const std::lock_guard lock(mutex_);
        search_ = {.running = true,
                   .method = method_name(job.method),
                   .names = space.names,
                   .bounds = space.bounds(),
                   .out_dir = job.out_dir,
                   .generation = search_.generation + 1};
    }
    SearchRequest request{.settings = search_settings(job.scene), .control = &control_};
    request.settings.method = job.method;
    if (job.method != SearchMethod::Auto) request.settings.rays = {request.settings.rays.back()};
    // (The panel's "preparing" line covers the tailoring: the desired far field is traced
    // for it, then the edge-ray designs.)
    if (job.tailored_start) set_tailored_start(*ctx_, job.scene, request);
    // Its folder holds what a command's does as it goes (options.json, then history.csv a
    // row a candidate), so it can be followed from another window or a shell (fird follow).
    std::unique_ptr<HistoryWriter> history;
    if (!job.out_dir.empty()) {
        write_text_file(
            (std::filesystem::path(job.out_dir) / "options.json").string(),
            search_options_json(request.settings, job.scene, request.start_report).dump(2) + "\n");
        history = std::make_unique<HistoryWriter>(
            (std::filesystem::path(job.out_dir) / "history.csv").string(), space.names, false,
            job.scene.optimize);
    }
    auto last_view = std::chrono::steady_clock::now() - std::chrono::hours(1);
    std::optional<FarField> view_target; // the target reflector at kBestViewRays
    double best = HUGE_VAL;
    std::uint32_t best_stage = ~0u;
    request.on_candidate = [&](const Candidate& c, const StageSummary& s) {
        if (history) history->write(c, s);
        ++evaluations_;
        if (c.feasible && !c.replayed) rays_traced_ += s.fidelity.rays;
        {
            const std::lock_guard lock(mutex_);
            search_.history.push_back(c);
            if (search_.stages.size() <= c.stage) search_.stages.resize(c.stage + 1);
            search_.stages[c.stage] = s;
            ++search_.generation;
        }
        if (c.stage != best_stage) best_stage = c.stage, best = HUGE_VAL;
        if (!c.feasible || !(c.score < best)) return;
        best = c.score;
        // The current best in the viewport, now and then (a low-ray view).
        const auto now = std::chrono::steady_clock::now();
        if (std::chrono::duration<double>(now - last_view).count() < kBestViewEvery_s) return;
        last_view = now;
        const auto params = space.named(c.x);
        // Its paths are rays of the scene's rayset, as the full trace's (a pick follows).
        render::TracedScene view = render::trace_for_views(*ctx_, job.scene,
                                                           {.parameters = params,
                                                            .rays = kBestViewRays,
                                                            .rayset_rays = job.scene.trace.rays,
                                                            .target_farfield = view_target});
        if (job.scene.target.kind == TargetDesc::Kind::Reflector && !view_target)
            view_target = view.farfield.desired; // the target does not change in a search
        publish(std::move(view), params, kBestViewRays, true);
    };
    SearchOutcome outcome = run_search(*ctx_, job.scene, request);
    if (!job.out_dir.empty()) {
        write_search_outputs(job.out_dir, job.scene, outcome);
        (void)export_search_reflectors(job.scene, outcome.result, job.out_dir);
    }
    const SearchResult& r = outcome.result;
    log(fmt::format("{} search: {} evaluations, stopped: {}, best {} {:.5g} {}{}", r.method,
                    r.history.size(), stop_reason_name(r.stopped), r.metric, r.best_l2_lm,
                    r.metric_unit, job.out_dir.empty() ? "" : ", files in " + job.out_dir));
    if (r.best)
        publish(render::trace_for_views(*ctx_, job.scene, {.parameters = r.best_parameters}),
                r.best_parameters, job.scene.trace.rays, false);
    const std::lock_guard lock(mutex_);
    search_.result = r;
    search_.running = false;
    ++search_.generation;
}

void Worker::run(const CalibrateJob& job) {
    {
        const std::lock_guard lock(mutex_);
        calibration_ = {.running = true,
                        .kind = job.rays_table ? "rays" : "semivariogram",
                        .out_dir = job.out_dir,
                        .generation = calibration_.generation + 1};
    }
    const auto progress = [&](std::size_t, std::uint32_t, double l2) {
        ++evaluations_;
        const std::lock_guard lock(mutex_);
        calibration_.partial.push_back(l2);
        ++calibration_.generation;
    };
    if (job.rays_table) {
        RaysTable t =
            calibrate_rays(*ctx_, job.scene, {.counts = {1000, 10000, 100000, 1000000}, .runs = 20},
                           &control_, progress);
        if (!job.out_dir.empty()) write_rays_table(job.out_dir, t, job.scene.name);
        log(fmt::format("calibrate rays: {} counts, slope {:.3f} ({:.1f} s)", t.rows.size(),
                        t.slope, t.time_s));
        const std::lock_guard lock(mutex_);
        calibration_.rays = std::move(t);
    } else {
        SemivariogramOptions o{.points = 41, .rays = 1000000};
        if (!job.parameter.empty()) o.parameters = {job.parameter};
        SemivariogramResult r = calibrate_semivariogram(*ctx_, job.scene, o, &control_, progress);
        if (!job.out_dir.empty()) write_semivariograms(job.out_dir, r, job.scene.name);
        for (const auto& p : r.parameters)
            log(fmt::format("semivariogram of {}: {} model, range {:.4g}, nugget {:.4g}",
                            p.parameter, variogram_model_name(p.model.model), p.model.range,
                            p.model.nugget));
        const std::lock_guard lock(mutex_);
        calibration_.semivariogram = std::move(r);
    }
    const std::lock_guard lock(mutex_);
    calibration_.running = false;
    ++calibration_.generation;
}

void Worker::run(const ToleranceJob& job) {
    {
        const std::lock_guard lock(mutex_);
        tolerance_ = {.running = true,
                      // The nominal luminaire, then each run's realisations (run_tolerance).
                      .total = 1 + job.tolerances.realisations *
                                       (1 + active_tolerances(job.tolerances).size()),
                      .scene_name = job.scene.name,
                      .out_dir = job.out_dir,
                      .generation = tolerance_.generation + 1};
    }
    // As fird tolerance runs it: the perturbed meshes go to (and leave) the run folder.
    const ToleranceRun run{.tolerances = job.tolerances,
                           .seed = job.seed,
                           .scratch_dir = job.out_dir,
                           .progress =
                               [&](const RealisationResult& row, std::size_t, std::size_t total) {
                                   ++evaluations_;
                                   const std::lock_guard lock(mutex_);
                                   tolerance_.rows.push_back(row);
                                   tolerance_.total = total;
                                   ++tolerance_.generation;
                               },
                           .stop = &control_.stop};
    ToleranceResult r = run_tolerance(*ctx_, job.scene, run);
    if (!job.out_dir.empty()) write_tolerance_outputs(job.out_dir, job.scene, r);
    log(fmt::format("tolerance: {} realisations{}, moves {} most: {} ({:.1f} s){}",
                    r.tolerances.realisations, r.stopped ? " (stopped)" : "", r.ranked_by,
                    r.most_sensitive, r.time_s,
                    job.out_dir.empty() ? "" : ", files in " + job.out_dir));
    const std::lock_guard lock(mutex_);
    tolerance_.result = std::move(r);
    tolerance_.running = false;
    ++tolerance_.generation;
}

} // namespace fird::ui
