#include "semivariogram_shares.hpp"

#include <algorithm>
#include <memory>
#include <optional>

namespace fird::distributed {

DistributedSeries semivariogram_tracing(Farm& farm) {
    return {.processes = std::size_t(farm.ranks()),
            .trace = [&farm](std::span<const SeriesPoint> points, const FarField& desired,
                             const SeriesTracer& here) {
                farm.set_setup_once(&desired);
                std::vector<double> l2s(points.size());
                farm.share({.items = points.size(),
                            .request =
                                [&](std::size_t first, std::size_t last) {
                                    Writer w;
                                    w.put(std::uint64_t(last - first));
                                    for (std::size_t k = first; k < last; ++k) {
                                        w.put(points[k].parameter);
                                        w.put(points[k].x);
                                        w.put(points[k].seed);
                                    }
                                    return w.bytes;
                                },
                            .here =
                                [&](std::size_t first, std::size_t last) {
                                    const std::vector<double> mine =
                                        here(points.subspan(first, last - first));
                                    std::copy(mine.begin(), mine.end(), l2s.begin() + first);
                                },
                            .answer =
                                [&](std::size_t first, std::size_t last, Reader& in) {
                                    for (std::size_t k = first; k < last; ++k)
                                        l2s[k] = in.get<double>();
                                }});
                return l2s;
            }};
}

ShareWorker semivariogram_worker(const vk::Context& ctx, const Scene& scene,
                                 const SemivariogramOptions& options) {
    struct State {
        std::optional<Evaluator> evaluator;
    };
    auto state = std::make_shared<State>();
    return {.setup =
                [state, &ctx, &scene, &options](const Bytes& bytes) {
                    Reader in{bytes};
                    std::optional<FarField> f = in.farfield();
                    if (!f) throw std::runtime_error("the semivariogram's setup has no far field");
                    // As calibrate_semivariogram's: the scene's fidelity at the series' rays.
                    Fidelity fidelity = scene_fidelity(scene);
                    fidelity.rays = options.rays;
                    state->evaluator.emplace(ctx, scene, fidelity);
                    state->evaluator->set_desired(*f);
                },
            .work =
                [state, &scene](const Bytes& bytes) {
                    if (!state->evaluator)
                        throw std::runtime_error("a semivariogram share came before its setup");
                    Reader in{bytes};
                    std::vector<SeriesPoint> points(in.get<std::uint64_t>());
                    for (SeriesPoint& p : points) {
                        p.parameter = in.text();
                        p.x = in.get<double>();
                        p.seed = in.get<std::uint64_t>();
                    }
                    Writer out;
                    for (const double l2 : trace_series_points(*state->evaluator, scene, points))
                        out.put(l2);
                    return out.bytes;
                }};
}

} // namespace fird::distributed
