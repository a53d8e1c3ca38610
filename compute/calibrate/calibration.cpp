#include "calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/desired_farfield.hpp"
#include "evaluation/evaluator.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search.hpp"

namespace fird {

namespace {

// Seed streams of a calibration (stream_seed): the desired trace, then one per run or
// point; far from the optimizer's streams, and never the target's seed.
constexpr std::uint64_t kDesiredStream = 7000;
constexpr std::uint64_t kRunStreams = 1u << 20;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::uint64_t avoid_seed(const Scene& s) {
    return s.target.kind == TargetDesc::Kind::Reflector ? s.target.seed : ~0ull;
}

void check_stop(const SearchControl* control) {
    if (control && control->stop.load())
        throw std::runtime_error("calibration stopped before it finished");
}

// The desired far field on the scene's grid: the desired reflector traced once at
// `rays` with its own stream, or the photometric target scaled to that trace's flux.
DesiredFarField calibration_desired(const vk::Context& ctx, const Scene& scene, std::uint64_t rays,
                                    std::uint64_t seed) {
    Fidelity f = scene_fidelity(scene);
    f.rays = rays;
    f.seed = stream_seed(seed, kDesiredStream, avoid_seed(scene));
    Evaluator desired(ctx, scene, f);
    const CandidateResult r = desired.evaluate(desired_reflector(scene));
    if (scene.target.kind == TargetDesc::Kind::Photometric)
        return desired_farfield(ctx, scene, r.farfield_lm);
    return {.farfield = desired.farfield(),
            .description = fmt::format("the desired reflector traced with {} rays", rays)};
}

} // namespace

ReflectorDesc desired_reflector(const Scene& scene) {
    return scene.target.kind == TargetDesc::Kind::Reflector ? target_reflector(scene)
                                                            : scene.reflector;
}

RaysTable calibrate_rays(const vk::Context& ctx, const Scene& scene, const RaysTableOptions& o,
                         const SearchControl* control, const RunCallback& on_run) {
    const auto t0 = std::chrono::steady_clock::now();
    if (o.counts.empty() || o.runs == 0)
        throw std::invalid_argument("calibrate rays: needs counts and at least one run");
    for (std::uint64_t n : o.counts)
        if (n == 0) throw std::invalid_argument("calibrate rays: a ray count of 0");
    RaysTable table;
    const bool photometric = scene.target.kind == TargetDesc::Kind::Photometric;
    const std::uint64_t largest = *std::max_element(o.counts.begin(), o.counts.end());
    table.desired_rays = o.desired_rays ? o.desired_rays : 10 * largest;
    const DesiredFarField desired = calibration_desired(ctx, scene, table.desired_rays, o.seed);
    table.desired = desired.description;
    if (photometric) table.desired_rays = 0;
    // The noise a histogram of n rays has about its mean (multinomial cells):
    // E[l2^2] = flux^2 sum p_i (1 - p_i) (1/n + 1/N_desired), p_i from the desired.
    const double flux = scene.source.flux_lm;
    double sum_p = 0.0;
    for (double v : desired.farfield.lm) {
        const double p = v / flux;
        sum_p += p * (1.0 - p);
    }
    const ReflectorDesc reflector = desired_reflector(scene);
    for (std::size_t c = 0; c < o.counts.size(); ++c) {
        const auto tc = std::chrono::steady_clock::now();
        Fidelity f = scene_fidelity(scene);
        f.rays = o.counts[c];
        Evaluator evaluator(ctx, scene, f); // pipelines and buffers once per count
        evaluator.set_desired(desired.farfield);
        double sum = 0.0, sum2 = 0.0;
        for (std::uint32_t run = 0; run < o.runs; ++run) {
            check_stop(control);
            evaluator.set_seed(stream_seed(o.seed, kRunStreams * (c + 1) + run, avoid_seed(scene)));
            const double l2 = *evaluator.evaluate(reflector).l2_lm;
            sum += l2;
            sum2 += l2 * l2;
            if (on_run) on_run(c, run, l2);
        }
        RaysRow row{.rays = o.counts[c], .runs = o.runs};
        row.mean_l2 = sum / o.runs;
        row.var_l2 = o.runs > 1 ? std::max(0.0, (sum2 - sum * row.mean_l2) / (o.runs - 1)) : 0.0;
        const double inv_desired = photometric ? 0.0 : 1.0 / double(table.desired_rays);
        row.predicted_l2 = flux * std::sqrt(sum_p * (1.0 / double(o.counts[c]) + inv_desired));
        row.time_s = seconds_since(tc);
        table.rows.push_back(row);
    }
    // Least squares of log mean against log rays.
    if (table.rows.size() >= 2) {
        double sx = 0, sy = 0, sxx = 0, sxy = 0;
        const double n = double(table.rows.size());
        for (const RaysRow& r : table.rows) {
            const double x = std::log(double(r.rays)), y = std::log(std::max(r.mean_l2, 1e-300));
            sx += x, sy += y, sxx += x * x, sxy += x * y;
        }
        table.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    }
    table.time_s = seconds_since(t0);
    return table;
}

namespace {

// The sample variance of l2 over independent traces of the centre reflector (fresh rays
// each, the same stream numbering as the series so no seed is reused).
double noise_variance(Evaluator& evaluator, const Scene& scene, const ReflectorDesc& centre,
                      const SemivariogramOptions& o, std::uint64_t& stream,
                      const SearchControl* control) {
    if (o.noise_runs < 2 || !candidate_feasibility(scene, centre).feasible) return 0.0;
    double sum = 0.0, sum2 = 0.0;
    for (std::uint32_t r = 0; r < o.noise_runs; ++r) {
        check_stop(control);
        evaluator.set_seed(stream_seed(o.seed, ++stream, avoid_seed(scene)));
        const double l2 = *evaluator.evaluate(centre).l2_lm;
        sum += l2, sum2 += l2 * l2;
    }
    const double n = o.noise_runs;
    return std::max(0.0, (sum2 - sum * sum / n) / (n - 1.0));
}

} // namespace

SemivariogramResult calibrate_semivariogram(const vk::Context& ctx, const Scene& scene,
                                            const SemivariogramOptions& o,
                                            const SearchControl* control,
                                            const PointCallback& on_point) {
    const auto t0 = std::chrono::steady_clock::now();
    const ParameterSpace space = parameter_space(scene);
    if (o.points < 3)
        throw std::invalid_argument(fmt::format(
            "--points {}: a semivariogram needs at least 3 points along the parameter", o.points));
    if (o.rays == 0) throw std::invalid_argument("--rays must be at least 1");
    std::vector<std::string> names = o.parameters.empty() ? space.names : o.parameters;
    for (const std::string& n : names)
        if (std::find(space.names.begin(), space.names.end(), n) == space.names.end())
            throw std::invalid_argument(
                fmt::format("--parameter {}: not in {}'s [reflector.optimize] ({})", n, scene.path,
                            fmt::join(space.names, ", ")));
    SemivariogramResult result{.rays = o.rays, .points = o.points};
    Fidelity f = scene_fidelity(scene);
    f.rays = o.rays;
    const DesiredFarField desired =
        calibration_desired(ctx, scene, std::max(scene.trace.rays, 10 * o.rays), o.seed);
    result.desired = desired.description;
    Evaluator evaluator(ctx, scene, f);      // one for the whole series: only the rays and
    evaluator.set_desired(desired.farfield); // the height field change between points
    const ReflectorDesc centre = desired_reflector(scene);
    std::uint64_t stream = kRunStreams * 64;
    result.noise_variance_l2 = noise_variance(evaluator, scene, centre, o, stream, control);
    for (std::size_t p = 0; p < names.size(); ++p) {
        const auto tp = std::chrono::steady_clock::now();
        const auto k = std::size_t(std::find(space.names.begin(), space.names.end(), names[p]) -
                                   space.names.begin());
        ParameterSemivariogram s{.parameter = names[p]};
        const double spacing = (space.hi[k] - space.lo[k]) / (o.points - 1);
        for (std::uint32_t j = 0; j < o.points; ++j) {
            check_stop(control);
            ReflectorDesc r = centre;
            const double x = space.lo[k] + j * spacing;
            r.parameters[names[p]] = x;
            s.x.push_back(x);
            double l2 = std::numeric_limits<double>::quiet_NaN();
            ++stream;
            if (candidate_feasibility(scene, r).feasible) {
                // Fresh rays per point, so its noise is in the series as in the paper.
                evaluator.set_seed(stream_seed(o.seed, stream, avoid_seed(scene)));
                l2 = *evaluator.evaluate(r).l2_lm;
            }
            s.l2.push_back(l2);
            if (on_point) on_point(p, j, l2);
        }
        s.empirical = empirical_semivariogram(s.l2, spacing);
        s.fits = fit_variograms(s.empirical);
        s.model = best_fit(s.fits);
        s.recommended_step = s.model.range;
        s.resolvable_step = resolvable_step(s.model, result.noise_variance_l2);
        s.time_s = seconds_since(tp);
        result.parameters.push_back(std::move(s));
    }
    result.time_s = seconds_since(t0);
    return result;
}

double calibrated_step(const ParameterSemivariogram& p, StepRule rule) {
    const double step = rule == StepRule::Resolvable
                            ? p.resolvable_step.value_or(0.0)
                            : std::max(p.recommended_step, p.resolvable_step.value_or(0.0));
    if (!(step > 0.0)) return step;
    const double mag = std::pow(10.0, std::floor(std::log10(step)) - 1.0);
    return std::ceil(step / mag - 1e-9) * mag;
}

Scene scene_with_steps(const Scene& scene, const SemivariogramResult& result, StepRule rule) {
    Scene s = scene;
    for (const ParameterSemivariogram& p : result.parameters) {
        const double step = calibrated_step(p, rule);
        if (step > 0.0) s.reflector.optimize.at(p.parameter).step = step;
    }
    return s;
}

} // namespace fird
