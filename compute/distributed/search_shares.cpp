#include "search_shares.hpp"

#include <memory>
#include <optional>

namespace fird::distributed {

DistributedTrace search_tracing(Farm& farm, Backend backend) {
    return {.processes = std::size_t(farm.ranks()), .trace = [&farm, backend](const StageBatch& b) {
                farm.set_setup_once(&b.desired);
                std::vector<CandidateResult> results(b.points.size());
                farm.share({.items = b.points.size(),
                            .request =
                                [&](std::size_t first, std::size_t last) {
                                    Writer w;
                                    const Fidelity& f = b.fidelity;
                                    for (std::uint64_t v :
                                         {std::uint64_t(backend), f.rays, f.seed,
                                          std::uint64_t(f.farfield_w), std::uint64_t(f.farfield_h),
                                          std::uint64_t(f.heightfield_w),
                                          std::uint64_t(f.heightfield_h),
                                          std::uint64_t(last - first),
                                          std::uint64_t(b.points[first].size())})
                                        w.put(v);
                                    for (std::size_t k = first; k < last; ++k)
                                        w.put(std::span<const double>(b.points[k]));
                                    return w.bytes;
                                },
                            .here =
                                [&](std::size_t first, std::size_t last) {
                                    std::vector<CandidateResult> here =
                                        b.trace_here(b.points.subspan(first, last - first));
                                    std::move(here.begin(), here.end(), results.begin() + first);
                                },
                            .answer =
                                [&](std::size_t first, std::size_t last, Reader& in) {
                                    for (std::size_t k = first; k < last; ++k) {
                                        results[k].l2_lm = in.get<double>();
                                        results[k].farfield_lm = in.get<double>();
                                        results[k].wall_ms = in.get<double>();
                                    }
                                }});
                return results;
            }};
}

ShareWorker search_worker(PointTracer& tracer) {
    auto desired = std::make_shared<FarField>();
    return {.setup =
                [desired](const Bytes& bytes) {
                    Reader in{bytes};
                    std::optional<FarField> f = in.farfield();
                    if (!f) throw std::runtime_error("the search's setup has no desired far field");
                    *desired = std::move(*f);
                },
            .work =
                [desired, &tracer](const Bytes& bytes) {
                    Reader in{bytes};
                    const Backend backend = Backend(in.get<std::uint64_t>());
                    Fidelity f;
                    f.rays = in.get<std::uint64_t>();
                    f.seed = in.get<std::uint64_t>();
                    f.farfield_w = std::uint32_t(in.get<std::uint64_t>());
                    f.farfield_h = std::uint32_t(in.get<std::uint64_t>());
                    f.heightfield_w = std::uint32_t(in.get<std::uint64_t>());
                    f.heightfield_h = std::uint32_t(in.get<std::uint64_t>());
                    const std::size_t n = in.get<std::uint64_t>(), dim = in.get<std::uint64_t>();
                    std::vector<std::vector<double>> points(n, std::vector<double>(dim));
                    for (std::vector<double>& x : points)
                        in.get(x);
                    Writer out;
                    for (const CandidateResult& r : tracer.trace(f, backend, *desired, points)) {
                        out.put(r.l2_lm.value_or(0.0));
                        out.put(r.farfield_lm);
                        out.put(r.wall_ms);
                    }
                    return out.bytes;
                }};
}

} // namespace fird::distributed
