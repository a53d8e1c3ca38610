#include "tolerance_shares.hpp"

#include <memory>
#include <optional>

namespace fird::distributed {

namespace {

void put_row(Writer& w, const RealisationResult& r) {
    w.put(r.draw);
    w.put(r.surface_rms_mm);
    w.put(std::uint8_t(r.l2_lm.has_value()));
    w.put(r.l2_lm.value_or(0.0));
    w.put(r.efficiency);
    w.put(r.peak_cd);
    w.put(r.beam_angle_deg);
    w.put(std::uint8_t(r.feasible));
}

RealisationResult get_row(Reader& in, const RealisationKey& key) {
    RealisationResult r{.kind = key.kind, .realisation = key.realisation};
    r.draw = in.get<ToleranceDraw>();
    r.surface_rms_mm = in.get<double>();
    const bool has_l2 = in.get<std::uint8_t>() != 0;
    const double l2 = in.get<double>();
    if (has_l2) r.l2_lm = l2;
    r.efficiency = in.get<double>();
    r.peak_cd = in.get<double>();
    r.beam_angle_deg = in.get<double>();
    r.feasible = in.get<std::uint8_t>() != 0;
    return r;
}

} // namespace

DistributedRealisations tolerance_tracing(Farm& farm) {
    return {.processes = std::size_t(farm.ranks()),
            .trace = [&farm](std::span<const RealisationKey> keys, const FarField* desired,
                             const RealisationTracer& here) {
                farm.set_setup_once(desired);
                std::vector<RealisationResult> rows(keys.size());
                farm.share({.items = keys.size(),
                            .request =
                                [&](std::size_t first, std::size_t last) {
                                    Writer w;
                                    w.put(std::uint64_t(last - first));
                                    for (std::size_t k = first; k < last; ++k) {
                                        w.put(keys[k].kind);
                                        w.put(keys[k].realisation);
                                    }
                                    return w.bytes;
                                },
                            .here =
                                [&](std::size_t first, std::size_t last) {
                                    std::vector<RealisationResult> mine =
                                        here(keys.subspan(first, last - first));
                                    std::move(mine.begin(), mine.end(), rows.begin() + first);
                                },
                            .answer =
                                [&](std::size_t first, std::size_t last, Reader& in) {
                                    for (std::size_t k = first; k < last; ++k)
                                        rows[k] = get_row(in, keys[k]);
                                }});
                return rows;
            }};
}

ShareWorker tolerance_worker(const vk::Context& ctx, const Scene& scene, const ToleranceRun& run) {
    auto desired = std::make_shared<std::optional<FarField>>();
    return {.setup =
                [desired](const Bytes& bytes) {
                    Reader in{bytes};
                    *desired = in.farfield();
                },
            .work =
                [desired, &ctx, &scene, &run](const Bytes& bytes) {
                    Reader in{bytes};
                    std::vector<RealisationKey> keys(in.get<std::uint64_t>());
                    for (RealisationKey& k : keys) {
                        k.kind = in.text();
                        k.realisation = in.get<std::uint64_t>();
                    }
                    Writer out;
                    for (const RealisationResult& r :
                         trace_realisations(ctx, scene, run, keys, *desired ? &**desired : nullptr))
                        put_row(out, r);
                    return out.bytes;
                }};
}

} // namespace fird::distributed
