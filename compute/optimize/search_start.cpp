#include "search_start.hpp"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "model/press_measures.hpp"
#include "model/surface.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search.hpp"
#include "optimize/tailored_start.hpp"

namespace fird {

namespace {

// The quick trace's rays: a stream of the search's seed apart from its stages' (0, 1, ...),
// its final and noise runs' (search.cpp's 1000 and 1001), the stage noise pair's (1002) and
// the population generator's (1003).
constexpr std::uint64_t kTailoredStream = 1004;
// The source's polar distribution: 0.1 degree bands from 2e5 of its rays (a band near the
// nadir holds few, but the flux map reads their sum, whose noise is 1/sqrt of the rays in
// the cone: about 0.3 % at 10 degrees for an isotropic source).
constexpr std::uint64_t kSourceRays = 200000;
constexpr std::uint32_t kSourceBands = 1800;

bool is_height(const std::string& name) {
    return name.size() > 2 && name.compare(0, 2, "h_") == 0 &&
           name.find_first_not_of("0123456789", 2) == std::string::npos;
}

} // namespace

std::optional<std::string> tailored_start_refusal(const Scene& scene) {
    if (scene.reflector.family != Family::Profile)
        return fmt::format("a tailored start is a profile's, and {} has the {} family", scene.path,
                           family_name(scene.reflector.family));
    for (const auto& entry : scene.reflector.optimize)
        if (is_height(entry.first)) return std::nullopt;
    return fmt::format("{}: [reflector.optimize] frees none of the profile's heights h_<k>",
                       scene.path);
}

SearchStartPoint tailored_start(const vk::Context& ctx, const Scene& scene, const FarField& desired,
                                const SearchSettings& settings) {
    if (const auto why = tailored_start_refusal(scene)) throw std::invalid_argument(*why);
    const ParameterSpace space = parameter_space(scene);
    // The scene's start: its apex (z0 + h_0) stays where it is, the rest is tailored.
    const Scene start = space.candidate(scene, space.start);
    const std::map<std::string, double>& p = start.reflector.parameters;
    const double z0 = p.at("z0");
    const double h0 = bspline_heights(start.reflector.bspline, p).front();
    const double source_z = start.source.center_mm.z;
    TailoringProblem problem{.source_band_lm =
                                 source_nadir_bands_lm(start.source, kSourceRays, kSourceBands),
                             .target_band_lm = farfield_zenith_bands_lm(desired),
                             .apex_depth_mm = source_z - (z0 + h0),
                             .radius_mm = p.at("radius_mm"),
                             .heights = start.reflector.bspline.nx};

    Fidelity quick = search_stages(scene, settings).front();
    quick.seed = stream_seed(settings.seed, kTailoredStream, streams_avoid(scene));
    Evaluator eval(ctx, start, quick, settings.backend);
    eval.set_desired(desired);
    SearchStartPoint best;
    best.report.kind = "tailored";
    double best_score = HUGE_VAL;
    StartReport tried;
    for (const EdgeRay edge : {EdgeRay::Crossing, EdgeRay::Diverging}) {
        const std::string name = edge_ray_name(edge);
        problem.edge = edge;
        TailoredProfile t;
        try {
            t = tailor_profile(problem);
        } catch (const std::invalid_argument& e) {
            tried.refused[name] = e.what();
            continue;
        }
        std::vector<double> x = space.start;
        std::vector<std::size_t> heights;
        std::vector<std::string> clamped;
        for (std::size_t i = 0; i < space.size(); ++i) {
            if (!is_height(space.names[i])) continue;
            const std::size_t k = std::stoul(space.names[i].substr(2));
            if (k >= t.z_mm.size()) continue;
            x[i] = source_z + t.z_mm[k] - z0;
            if (x[i] < space.lo[i] || x[i] > space.hi[i]) clamped.push_back(space.names[i]);
            heights.push_back(i);
        }
        const std::vector<double> snapped = space.snap(x); // clamps into the box too
        for (std::size_t i : heights)
            x[i] = snapped[i];
        const Scene candidate = space.candidate(scene, x);
        const Feasibility f = traceable(candidate, candidate.reflector);
        if (!f.feasible) {
            tried.refused[name] = f.reason;
            continue;
        }
        const double metric = *eval.evaluate(candidate.reflector).l2_lm;
        tried.quick_metric[name] = metric;
        // Chosen by what the search minimises: with a smoothness weight, the metric plus
        // the weighted bending energy (its score), else the metric itself.
        double score = metric;
        if (scene.optimize.smoothness > 0.0) {
            const double energy =
                search_bending_energy(Surface::make(candidate.reflector, candidate.holder));
            score = candidate_score(metric, energy, scene.optimize);
            tried.quick_score[name] = score;
        }
        if (score < best_score) {
            best_score = score;
            best.x = x;
            best.report.edge_ray = name;
            best.report.rim_polar_deg = t.rim_polar_rad * 180.0 / std::numbers::pi;
            best.report.source_share = t.source_share;
            best.report.reaches_rim = t.reaches_rim;
            best.report.target_share_left_out = t.target_share_left_out;
            best.report.clamped = clamped;
        }
    }
    best.report.quick_metric = tried.quick_metric;
    best.report.quick_score = tried.quick_score;
    best.report.refused = tried.refused;
    if (best.x.empty()) {
        std::string why;
        for (const auto& [edge, reason] : tried.refused)
            why += fmt::format("{}{}: {}", why.empty() ? "" : "; ", edge, reason);
        throw std::invalid_argument(fmt::format("{}: no tailored start ({})", scene.path, why));
    }
    return best;
}

void set_tailored_start(const vk::Context& ctx, const Scene& scene, SearchRequest& request) {
    const auto t0 = std::chrono::steady_clock::now();
    request.desired = search_desired(ctx, scene, request.settings);
    SearchStartPoint start =
        tailored_start(ctx, scene, request.desired->farfield, request.settings);
    request.start = std::move(start.x);
    request.start_report = std::move(start.report);
    request.start_report.parameters = parameter_space(scene).named(*request.start);
    request.start_report.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace fird
