#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "bench/bench.hpp"
#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "optimize/search.hpp"

namespace fird {

namespace {

double ms_of(const std::function<void()>& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

std::vector<SkipRow> run_skips_bench(const vk::Context& ctx, const std::vector<std::string>& paths,
                                     int reps,
                                     const std::function<void(const SkipRow&)>& progress) {
    std::vector<SkipRow> rows;
    const auto add = [&](SkipRow r) {
        if (progress) progress(r);
        rows.push_back(std::move(r));
    };
    for (const std::string& path : paths) {
        const Scene s = load_scene(path);
        const ReflectorDesc a = s.reflector;
        const ReflectorDesc b =
            s.target.kind == TargetDesc::Kind::Reflector ? target_reflector(s) : s.reflector;
        Evaluator ev(ctx, s, scene_fidelity(s));
        (void)ev.evaluate(a); // the rayset, pipelines and caches warm
        // One evaluation of a changed reflector (as a search makes them), with the skips
        // given, median over reps alternating the two reflectors.
        const auto eval_ms = [&](const FastPathSkips& skips, bool same_reflector) {
            ev.set_skips(skips);
            std::vector<double> t;
            for (int k = 0; k < reps; ++k)
                t.push_back(ms_of([&] { (void)ev.evaluate(same_reflector || k % 2 ? a : b); }));
            ev.set_skips({});
            return median_ms(t);
        };
        const FastPathSkips on{};
        // Alternate with and without, so drift hits both alike.
        const auto pair = [&](const char* name, FastPathSkips off, bool same, const char* note) {
            std::vector<double> with, without;
            for (int k = 0; k < 2; ++k) {
                with.push_back(eval_ms(on, same));
                without.push_back(eval_ms(off, same));
            }
            add({s.name, name, median_ms(with), median_ms(without), note});
        };
        pair("rayset kept while only the reflector changes", {.keep_rayset = false}, false,
             "each candidate of a search");
        pair("height field kept while the reflector is the same", {.keep_heightfield = false}, true,
             "re-traces of one reflector (fresh seeds, previews)");
        pair("rays that cannot meet the holder not traced", {.discard_before_trace = false}, false,
             "");
        pair("no dispatch for a bounce without active rays", {.skip_empty_bounces = false}, false,
             "");
        pair("rising rays leave at the reflector's highest point",
             {.end_walk_at_reflector_top = false}, false,
             "the holder's open top above the reflector");
        pair("the source's rays start below the nodes they must descend",
             {.start_walk_below_source = false}, false, "a source inside the holder box");
        // The compare pass a scene without a target skips: its cost alone.
        ev.set_desired(FarField{
            s.trace.farfield_w, s.trace.farfield_h,
            std::vector<double>(std::size_t(s.trace.farfield_w) * s.trace.farfield_h, 0.0)});
        std::vector<double> compare;
        for (int k = 0; k < reps; ++k)
            compare.push_back(ms_of([&] { (void)ev.compare(); }));
        add({s.name, "no compare pass without a target", 0.0, median_ms(compare),
             "the l2 reduction alone"});
    }
    return rows;
}

std::string skips_markdown(const std::vector<SkipRow>& rows, const std::string& device) {
    const bool ranks =
        std::any_of(rows.begin(), rows.end(), [](const SkipRow& r) { return r.rank > 0; });
    std::string s = fmt::format("Device: {}\n\n", device);
    s += "| scene | skip | with it ms | without it ms | saves ms | saves % | when |" +
         std::string(ranks ? " rank |\n" : "\n");
    s += "|---|---|---|---|---|---|---|" + std::string(ranks ? "---|\n" : "\n");
    for (const SkipRow& r : rows) {
        const double saved = r.without_ms - r.with_ms;
        s += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.1f} | {:.0f} % | {} |", r.scene, r.skip,
                         r.with_ms, r.without_ms, saved,
                         r.without_ms > 0 ? 100.0 * saved / r.without_ms : 0.0, r.note) +
             (ranks ? fmt::format(" {} |\n", r.rank) : std::string("\n"));
    }
    return s;
}

} // namespace fird
