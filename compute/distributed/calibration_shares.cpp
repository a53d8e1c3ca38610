#include "calibration_shares.hpp"

#include <algorithm>
#include <memory>
#include <optional>

namespace fird::distributed {

namespace {

void put_optional(Writer& w, const std::optional<double>& v) {
    w.put(std::uint8_t(v.has_value()));
    w.put(v.value_or(0.0));
}

std::optional<double> get_optional(Reader& in) {
    const bool has = in.get<std::uint8_t>() != 0;
    const double v = in.get<double>();
    return has ? std::optional(v) : std::nullopt;
}

} // namespace

DistributedRuns calibration_tracing(Farm& farm) {
    return {.processes = std::size_t(farm.ranks()),
            .trace = [&farm](std::size_t c, std::span<const std::uint32_t> firsts,
                             const FarField& desired, const RunPairTracer& here) {
                farm.set_setup_once(&desired);
                std::vector<RunPair> pairs(firsts.size());
                farm.share({.items = firsts.size(),
                            .request =
                                [&](std::size_t first, std::size_t last) {
                                    Writer w;
                                    w.put(std::uint64_t(c));
                                    w.put(std::uint64_t(last - first));
                                    for (std::size_t k = first; k < last; ++k)
                                        w.put(firsts[k]);
                                    return w.bytes;
                                },
                            .here =
                                [&](std::size_t first, std::size_t last) {
                                    const std::vector<RunPair> mine =
                                        here(c, firsts.subspan(first, last - first));
                                    std::copy(mine.begin(), mine.end(), pairs.begin() + first);
                                },
                            .answer =
                                [&](std::size_t first, std::size_t last, Reader& in) {
                                    for (std::size_t k = first; k < last; ++k) {
                                        pairs[k].first_l2_lm = in.get<double>();
                                        pairs[k].second_l2_lm = get_optional(in);
                                        pairs[k].between_l2_lm = get_optional(in);
                                    }
                                }});
                return pairs;
            }};
}

ShareWorker calibration_worker(const vk::Context& ctx, const Scene& scene,
                               const RaysTableOptions& options) {
    struct State {
        FarField desired;
        std::optional<Evaluator> evaluator;
        std::size_t row = 0;
    };
    auto state = std::make_shared<State>();
    return {.setup =
                [state](const Bytes& bytes) {
                    Reader in{bytes};
                    std::optional<FarField> f = in.farfield();
                    if (!f) throw std::runtime_error("the calibration's setup has no far field");
                    state->desired = std::move(*f);
                },
            .work =
                [state, &ctx, &scene, &options](const Bytes& bytes) {
                    Reader in{bytes};
                    const std::size_t c = in.get<std::uint64_t>();
                    if (c >= options.counts.size())
                        throw std::runtime_error("a calibration share names a row this rank lacks");
                    std::vector<std::uint32_t> firsts(in.get<std::uint64_t>());
                    for (std::uint32_t& run : firsts)
                        run = in.get<std::uint32_t>();
                    if (!state->evaluator || state->row != c) {
                        state->evaluator.reset(); // one row's buffers at a time
                        Fidelity f = scene_fidelity(scene);
                        f.rays = options.counts[c];
                        state->evaluator.emplace(ctx, scene, f);
                        state->evaluator->set_desired(state->desired);
                        state->row = c;
                    }
                    Writer out;
                    for (const RunPair& p :
                         trace_run_pairs(*state->evaluator, scene, options, c, firsts)) {
                        out.put(p.first_l2_lm);
                        put_optional(out, p.second_l2_lm);
                        put_optional(out, p.between_l2_lm);
                    }
                    return out.bytes;
                }};
}

} // namespace fird::distributed
