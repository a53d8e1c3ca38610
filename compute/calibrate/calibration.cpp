#include "calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/desired_farfield.hpp"
#include "evaluation/evaluator.hpp"
#include "model/design_parameters.hpp"
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

void check_stop(const SearchControl* control) {
    if (control && control->stop.load())
        throw std::runtime_error("calibration stopped before it finished");
}

// The desired far field on the scene's grid: the desired reflector traced once at `rays`
// with its own stream, or the photometric target scaled to that trace's flux. With
// `noise_lm2` the desired reflector is traced a second time (the next stream) and half the
// squared l2 between the two traces is the desired's own noise, measured (0 for a
// photometric target, which has none).
DesiredFarField calibration_desired(const vk::Context& ctx, const Scene& scene, std::uint64_t rays,
                                    std::uint64_t seed, double* noise_lm2 = nullptr) {
    Fidelity f = scene_fidelity(scene);
    f.rays = rays;
    f.seed = stream_seed(seed, kDesiredStream, streams_avoid(scene));
    Evaluator desired(ctx, scene, f);
    const CandidateResult r = desired.evaluate(desired_reflector(scene));
    if (scene.target.kind == TargetDesc::Kind::Photometric) {
        if (noise_lm2) *noise_lm2 = 0.0;
        return desired_farfield(ctx, scene, r.farfield_lm);
    }
    DesiredFarField d{.farfield = desired.farfield(),
                      .description =
                          fmt::format("the desired reflector traced with {} rays", rays)};
    if (noise_lm2) {
        desired.set_seed(stream_seed(seed, kDesiredStream + 1, streams_avoid(scene)));
        (void)desired.evaluate(desired_reflector(scene));
        const double l2 = farfield_distance(d.farfield, desired.farfield(), desired.metric());
        *noise_lm2 = 0.5 * l2 * l2;
    }
    return d;
}

double least_squares_slope(const std::vector<RaysRow>& rows) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = double(rows.size());
    for (const RaysRow& r : rows) {
        const double x = std::log(double(r.rays)), y = std::log(std::max(r.mean_l2, 1e-300));
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

} // namespace

const char* noise_prediction_name(NoisePrediction p) {
    return p == NoisePrediction::Multinomial ? "multinomial" : "replicate";
}

NoisePrediction noise_prediction_for(SamplerKind sampler) {
    return sampler == SamplerKind::Random ? NoisePrediction::Multinomial
                                          : NoisePrediction::Replicate;
}

std::string noise_prediction_label(SamplerKind sampler) {
    return noise_prediction_for(sampler) == NoisePrediction::Multinomial
               ? "noise alone, independent rays (random sampler): multinomial formula"
               : fmt::format("noise alone, {} sampler: measured from replicate traces",
                             sampler_name(sampler));
}

const char* step_rule_name(StepRule rule) {
    return rule == StepRule::Resolvable ? "resolvable" : "range";
}

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
    RaysTable table{.sampler = scene.trace.sampler,
                    .prediction = noise_prediction_for(scene.trace.sampler)};
    const bool photometric = scene.target.kind == TargetDesc::Kind::Photometric;
    const std::uint64_t largest = *std::max_element(o.counts.begin(), o.counts.end());
    table.desired_rays = o.desired_rays ? o.desired_rays : 10 * largest;
    double desired_noise_lm2 = 0.0; // V_N, measured
    const DesiredFarField desired =
        calibration_desired(ctx, scene, table.desired_rays, o.seed, &desired_noise_lm2);
    table.desired = desired.description;
    table.metric = scene.optimize.metric;
    if (photometric) table.desired_rays = 0;
    // Independent rays: E[l2^2] = flux^2 sum p (1 - p) (1/n + 1/N), p from the desired.
    const double multinomial = multinomial_noise_lm2_times_rays(
        desired.farfield, scene.source.flux_lm, scene.optimize.metric);
    for (std::size_t c = 0; c < o.counts.size(); ++c) {
        const auto tc = std::chrono::steady_clock::now();
        Fidelity f = scene_fidelity(scene);
        f.rays = o.counts[c];
        // Pipelines and buffers once per count (made when this process first traces a pair).
        std::optional<Evaluator> evaluator;
        const RunPairTracer here = [&](std::size_t, std::span<const std::uint32_t> firsts) {
            if (!evaluator) {
                evaluator.emplace(ctx, scene, f);
                evaluator->set_desired(desired.farfield);
            }
            return trace_run_pairs(*evaluator, scene, o, c, firsts);
        };
        double sum = 0.0, sum2 = 0.0, pair_sum2 = 0.0;
        RaysRow row{.rays = o.counts[c], .runs = o.runs};
        std::vector<std::uint32_t> firsts;
        for (std::uint32_t run = 0; run < o.runs; run += 2)
            firsts.push_back(run);
        // A pair at a time here; across processes a few for each per exchange.
        const std::size_t chunk = o.distributed.trace ? 4 * o.distributed.processes : 1;
        for (std::size_t k = 0; k < firsts.size(); k += chunk) {
            check_stop(control);
            const auto part = std::span(firsts).subspan(k, std::min(chunk, firsts.size() - k));
            const std::vector<RunPair> pairs =
                o.distributed.trace ? o.distributed.trace(c, part, desired.farfield, here)
                                    : here(c, part);
            // Summed in the runs' order, whichever process traced them.
            for (std::size_t p = 0; p < pairs.size(); ++p) {
                const auto add = [&](std::uint32_t run, double l2) {
                    sum += l2;
                    sum2 += l2 * l2;
                    if (on_run) on_run(c, run, l2);
                };
                add(part[p], pairs[p].first_l2_lm);
                if (pairs[p].second_l2_lm) add(part[p] + 1, *pairs[p].second_l2_lm);
                if (pairs[p].between_l2_lm) {
                    const double d = *pairs[p].between_l2_lm;
                    pair_sum2 += d * d;
                    ++row.replicate_pairs;
                }
            }
        }
        row.mean_l2 = sum / o.runs;
        row.var_l2 = o.runs > 1 ? std::max(0.0, (sum2 - sum * row.mean_l2) / (o.runs - 1)) : 0.0;
        const double inv_desired = photometric ? 0.0 : 1.0 / double(table.desired_rays);
        row.multinomial_l2 = std::sqrt(multinomial * (1.0 / double(o.counts[c]) + inv_desired));
        row.replicate_l2 =
            row.replicate_pairs > 0
                ? std::sqrt(0.5 * pair_sum2 / row.replicate_pairs + desired_noise_lm2)
                : std::nan("");
        row.predicted_l2 = table.prediction == NoisePrediction::Multinomial ? row.multinomial_l2
                                                                            : row.replicate_l2;
        row.time_s = seconds_since(tc);
        table.rows.push_back(row);
    }
    if (table.rows.size() >= 2) table.slope = least_squares_slope(table.rows);
    table.time_s = seconds_since(t0);
    return table;
}

std::vector<RunPair> trace_run_pairs(Evaluator& evaluator, const Scene& scene,
                                     const RaysTableOptions& o, std::size_t c,
                                     std::span<const std::uint32_t> first_runs) {
    const ReflectorDesc reflector = desired_reflector(scene);
    const auto trace_run = [&](std::uint32_t run) {
        evaluator.set_seed(stream_seed(o.seed, kRunStreams * (c + 1) + run, streams_avoid(scene)));
        return *evaluator.evaluate(reflector).l2_lm;
    };
    std::vector<RunPair> pairs;
    for (const std::uint32_t run : first_runs) {
        RunPair p{.first_l2_lm = trace_run(run)};
        // Runs 2k and 2k + 1 are independent traces of one reflector: half their squared
        // l2 estimates V_n without a trace more (the far fields are read back only here).
        if (run + 1 < o.runs) {
            const FarField first = evaluator.farfield();
            p.second_l2_lm = trace_run(run + 1);
            p.between_l2_lm = farfield_distance(first, evaluator.farfield(), evaluator.metric());
        }
        pairs.push_back(p);
    }
    return pairs;
}

namespace {

// The replicate raysets of the noise: the desired reflector's l2 with each (fresh rays each,
// the same stream numbering as the series so no seed is reused).
struct NoiseReplicates {
    std::vector<std::uint64_t> seeds;
    std::vector<double> centre_l2;
    double variance_l2 = 0.0; // their sample variance: the fresh-ray noise of a point
};

NoiseReplicates noise_replicates(Evaluator& evaluator, const Scene& scene,
                                 const ReflectorDesc& centre, const SemivariogramOptions& o,
                                 std::uint64_t& stream, const SearchControl* control) {
    NoiseReplicates n;
    if (o.noise_runs < 2 || !candidate_feasibility(scene, centre).feasible) return n;
    double sum = 0.0, sum2 = 0.0;
    for (std::uint32_t r = 0; r < o.noise_runs; ++r) {
        check_stop(control);
        n.seeds.push_back(stream_seed(o.seed, ++stream, streams_avoid(scene)));
        evaluator.set_seed(n.seeds.back());
        const double l2 = *evaluator.evaluate(centre).l2_lm;
        n.centre_l2.push_back(l2);
        sum += l2, sum2 += l2 * l2;
    }
    const double runs = o.noise_runs;
    n.variance_l2 = std::max(0.0, (sum2 - sum * sum / runs) / (runs - 1.0));
    return n;
}

// The differences a search compares at lag h along parameter k: for each replicate rayset,
// l2(centre +- h) - l2(centre) traced with the same rays (a side outside the bounds or
// infeasible is left out).
std::vector<std::vector<double>>
common_random_differences(Evaluator& evaluator, const Scene& scene, const ParameterSpace& space,
                          std::size_t k, const ReflectorDesc& centre, const NoiseReplicates& n,
                          double lag, const SearchControl* control) {
    const std::string& name = space.names[k];
    const double x = centre.parameters.at(name);
    std::vector<ReflectorDesc> sides;
    for (double side : {x + lag, x - lag}) {
        ReflectorDesc r = centre;
        r.parameters[name] = side;
        if (side >= space.lo[k] && side <= space.hi[k] && candidate_feasibility(scene, r).feasible)
            sides.push_back(r);
    }
    std::vector<std::vector<double>> groups(sides.size());
    for (std::size_t r = 0; r < n.seeds.size(); ++r) {
        evaluator.set_seed(n.seeds[r]); // the rays the centre's l2 was traced with
        for (std::size_t s = 0; s < sides.size(); ++s) {
            check_stop(control);
            groups[s].push_back(*evaluator.evaluate(sides[s]).l2_lm - n.centre_l2[r]);
        }
    }
    return groups;
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
    // The semivariogram moves reflector parameters; the source's place is not calibrated.
    std::erase_if(names, [&](const std::string& n) {
        if (!is_source_parameter(n)) return false;
        if (!o.parameters.empty())
            throw std::invalid_argument(fmt::format(
                "--parameter {}: the source's place ([source.optimize]) is not calibrated", n));
        return true;
    });
    if (names.empty())
        throw std::invalid_argument(fmt::format(
            "{}: no reflector parameter to calibrate ([source.optimize]'s are not)", scene.path));
    for (const std::string& n : names)
        if (std::find(space.names.begin(), space.names.end(), n) == space.names.end())
            throw std::invalid_argument(
                fmt::format("--parameter {}: not in {}'s [reflector.optimize] ({})", n, scene.path,
                            fmt::join(space.names, ", ")));
    SemivariogramResult result{
        .rays = o.rays, .points = o.points, .noise_runs = o.noise_runs, .step_rule = o.step_rule};
    Fidelity f = scene_fidelity(scene);
    f.rays = o.rays;
    const DesiredFarField desired =
        calibration_desired(ctx, scene, std::max(scene.trace.rays, 10 * o.rays), o.seed);
    result.desired = desired.description;
    result.metric = scene.optimize.metric;
    Evaluator evaluator(ctx, scene, f);      // one for the whole series: only the rays and
    evaluator.set_desired(desired.farfield); // the height field change between points
    const ReflectorDesc centre = desired_reflector(scene);
    std::uint64_t stream = kRunStreams * 64;
    const NoiseReplicates noise = noise_replicates(evaluator, scene, centre, o, stream, control);
    result.noise_variance_l2 = noise.variance_l2;
    for (std::size_t p = 0; p < names.size(); ++p) {
        const auto tp = std::chrono::steady_clock::now();
        const auto k = std::size_t(std::find(space.names.begin(), space.names.end(), names[p]) -
                                   space.names.begin());
        ParameterSemivariogram s{.parameter = names[p]};
        const double spacing = (space.hi[k] - space.lo[k]) / (o.points - 1);
        // Fresh rays per point, so its noise is in the series as in the paper: each point's
        // seed follows from its place in the series, wherever it is traced.
        std::vector<SeriesPoint> points;
        std::vector<std::uint32_t> traced; // the series index of each point to trace
        for (std::uint32_t j = 0; j < o.points; ++j) {
            const double x = space.lo[k] + j * spacing;
            s.x.push_back(x);
            s.l2.push_back(std::numeric_limits<double>::quiet_NaN()); // infeasible: none
            ++stream;
            ReflectorDesc r = centre;
            r.parameters[names[p]] = x;
            if (!candidate_feasibility(scene, r).feasible) continue;
            points.push_back({names[p], x, stream_seed(o.seed, stream, streams_avoid(scene))});
            traced.push_back(j);
        }
        const SeriesTracer here = [&](std::span<const SeriesPoint> part) {
            return trace_series_points(evaluator, scene, part);
        };
        // A point at a time here; across processes a few for each per exchange.
        const std::size_t chunk = o.distributed.trace ? 4 * o.distributed.processes : 1;
        std::uint32_t shown = 0; // the series' points reported so far
        for (std::size_t first = 0; first < points.size(); first += chunk) {
            check_stop(control);
            const auto part =
                std::span(points).subspan(first, std::min(chunk, points.size() - first));
            const std::vector<double> l2s = o.distributed.trace
                                                ? o.distributed.trace(part, desired.farfield, here)
                                                : here(part);
            for (std::size_t i = 0; i < part.size(); ++i)
                s.l2[traced[first + i]] = l2s.at(i);
            const std::uint32_t upto =
                first + part.size() < points.size() ? traced[first + part.size()] : o.points;
            for (; shown < upto; ++shown)
                if (on_point) on_point(p, shown, s.l2[shown]);
        }
        for (; shown < o.points; ++shown)
            if (on_point) on_point(p, shown, s.l2[shown]);
        s.empirical = empirical_semivariogram(s.l2, spacing);
        s.fits = fit_variograms(s.empirical);
        s.model = best_fit(s.fits);
        s.recommended_step = s.model.range;
        if (!noise.seeds.empty()) {
            // Probed around the desired reflector, from the series' spacing; never past half
            // the span (the semivariogram's own reach).
            const Resolution res = resolvable_step(
                s.model,
                [&](double lag) {
                    return common_random_differences(evaluator, scene, space, k, centre, noise, lag,
                                                     control);
                },
                spacing, 0.5 * (space.hi[k] - space.lo[k]));
            s.resolvable_step = res.step;
            s.resolution = res.probes;
        }
        s.time_s = seconds_since(tp);
        result.parameters.push_back(std::move(s));
    }
    result.time_s = seconds_since(t0);
    return result;
}

std::vector<double> trace_series_points(Evaluator& evaluator, const Scene& scene,
                                        std::span<const SeriesPoint> points) {
    const ReflectorDesc centre = desired_reflector(scene);
    std::vector<double> l2s;
    for (const SeriesPoint& point : points) {
        ReflectorDesc r = centre;
        r.parameters[point.parameter] = point.x;
        evaluator.set_seed(point.seed);
        l2s.push_back(*evaluator.evaluate(r).l2_lm);
    }
    return l2s;
}

double calibrated_step(const ParameterSemivariogram& p, StepRule rule) {
    const double step = rule == StepRule::Resolvable
                            ? p.resolvable_step.value_or(0.0)
                            : std::max(p.recommended_step, p.resolvable_step.value_or(0.0));
    if (!(step > 0.0)) return step;
    const double mag = std::pow(10.0, std::floor(std::log10(step)) - 1.0);
    return std::ceil(step / mag - 1e-9) * mag;
}

Scene scene_with_steps(const Scene& scene, const SemivariogramResult& result) {
    Scene s = scene;
    for (const ParameterSemivariogram& p : result.parameters) {
        const double step = calibrated_step(p, result.step_rule);
        if (step > 0.0) s.reflector.optimize.at(p.parameter).step = step;
    }
    return s;
}

} // namespace fird
