// fird follow DIR: a search's progress read from its --out folder while it runs elsewhere
// (a cluster job, another terminal) or after it ended: a line for each stage it begins and
// each new best, the account at its end (optimize/search_folder.hpp).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include <fmt/format.h>

#include "commands.hpp"
#include "interrupt.hpp"
#include "io/atomic_file.hpp"
#include "optimize/search_folder.hpp"
#include "optimize/search_report.hpp"
#include "parse.hpp"
#include "progress.hpp"

namespace fird::app {

namespace {

struct FollowArgs {
    std::string dir, out;
    double interval_s = 2.0, idle_timeout_s = 3600.0;
    bool once = false, json = false;
};

std::string named_values(const FollowedSearch& f, const std::vector<double>& x) {
    std::string text;
    for (std::size_t k = 0; k < f.names.size() && k < x.size(); ++k)
        text += fmt::format("{}{}={:.6g}", k ? " " : "", f.names[k], x[k]);
    return text;
}

// What is new since `seen` rows: the stages begun and a new best, one line each.
void print_news(const FollowedSearch& f, std::size_t seen, std::optional<std::uint64_t>& best) {
    const auto& rows = f.rows.candidates;
    const char* metric = metric_name(f.scene.optimize.metric);
    const char* unit = metric_unit(f.scene.optimize.metric);
    for (std::size_t k = seen; k < rows.size(); ++k)
        if (k == 0 || rows[k].stage != rows[k - 1].stage) {
            const StageSummary& s = f.rows.stages[rows[k].stage];
            std::printf("%s",
                        fmt::format("evaluation {}: stage {} at {:.3g} rays ({}x{} far field)\n", k,
                                    s.name, double(s.fidelity.rays), s.fidelity.farfield_w,
                                    s.fidelity.farfield_h)
                            .c_str());
        }
    const Candidate* now = latest_stage_best(rows);
    if (now && (!best || *best != now->index)) {
        best = now->index;
        std::printf("%s", fmt::format("evaluation {}: best {} {:.6g} {} ({})\n", now->index, metric,
                                      now->l2_lm, unit, named_values(f, now->x))
                              .c_str());
    }
    std::fflush(stdout);
}

void print_end(const FollowedSearch& f) {
    const SearchResult r = followed_result(f);
    std::printf("%s", fmt::format("{}: {} search, {} evaluations ({} infeasible), stopped: {}, "
                                  "{:.1f} s\n",
                                  f.scene.name, f.method, r.history.size(), r.infeasible,
                                  f.end->stopped, f.end->time_s)
                          .c_str());
    if (!r.best_parameters.empty()) {
        std::string params;
        for (const auto& [k, v] : r.best_parameters)
            params += fmt::format(" {}={:.6g}", k, v);
        std::printf("best:%s\n", params.c_str());
    }
    if (r.final_l2_lm)
        std::printf("%s",
                    fmt::format("{} at the scene's rays: start {}, final {:.6g} {}{}\n", r.metric,
                                r.start_l2_lm ? fmt::format("{:.6g}", *r.start_l2_lm) : "-",
                                *r.final_l2_lm, r.metric_unit,
                                r.noise_floor_l2_lm
                                    ? fmt::format(" (noise floor {:.6g})", *r.noise_floor_l2_lm)
                                    : "")
                        .c_str());
}

int run_follow(const FollowArgs& a) {
    using clock = std::chrono::steady_clock;
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!a.out.empty() && fs::equivalent(a.out, a.dir, ec))
        throw UsageError("--out must not be the followed folder: its files are the search's");
    SearchControl control;
    const InterruptScope interrupts(control);
    const auto wait = [&] {
        // In short sleeps, so that Ctrl-C ends the wait at once.
        const auto until = clock::now() + std::chrono::duration<double>(a.interval_s);
        while (!control.stop.load() && clock::now() < until)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
    };
    auto last_news = clock::now();
    const auto idle = [&] {
        return std::chrono::duration<double>(clock::now() - last_news).count() > a.idle_timeout_s;
    };
    const bool text = !a.json;
    bool said_waiting = false;
    while (!search_began(a.dir)) {
        if (a.once || !std::filesystem::is_directory(a.dir))
            throw std::runtime_error(
                fmt::format("{}: no search has begun there (no options.json){}", a.dir,
                            std::filesystem::is_directory(a.dir) ? "" : ": no such folder"));
        if (text && !said_waiting)
            std::printf("waiting for the search in %s to begin (no options.json yet)\n",
                        a.dir.c_str()),
                std::fflush(stdout), said_waiting = true;
        if (idle())
            throw std::runtime_error(fmt::format(
                "{}: no search began in {} s (--idle-timeout); is its job queued or running?",
                a.dir, a.idle_timeout_s));
        wait();
        if (control.stop.load()) return 130;
    }
    FollowedSearch f = read_search_folder(a.dir);
    if (text)
        std::printf(
            "%s", fmt::format("following {}: {} ({} search of {}, at most {} evaluations)\n", a.dir,
                              f.scene.name, f.method, fmt::join(f.names, ", "), f.max_evaluations)
                      .c_str());
    std::size_t seen = 0;
    std::optional<std::uint64_t> best;
    last_news = clock::now();
    // A read that fails while the search runs is tried again (a file system shared between
    // machines may show a file's tail late); this many in a row end the follow.
    constexpr int kFailedReads = 5;
    int failed = 0;
    while (true) {
        if (text) print_news(f, seen, best);
        if (f.rows.candidates.size() != seen) last_news = clock::now();
        seen = f.rows.candidates.size();
        if (f.end || a.once || control.stop.load()) break;
        if (idle())
            throw std::runtime_error(fmt::format(
                "{}: no new row in {} s (--idle-timeout) after {} evaluations: the search may "
                "have stopped (its scene's run.sh, slurm.sh or fird optimize --resume {} "
                "continues it)",
                a.dir, a.idle_timeout_s, seen, a.dir));
        wait();
        try {
            refresh_search_folder(f);
            failed = 0;
        } catch (const std::exception&) {
            if (++failed == kFailedReads) throw;
        }
    }
    const nlohmann::json j = followed_search_json(f);
    if (!a.out.empty()) {
        create_output_directory(a.out);
        write_text_file((std::filesystem::path(a.out) / "follow.json").string(), j.dump(2) + "\n");
        write_progress_png((std::filesystem::path(a.out) / "progress.png").string(),
                           followed_result(f));
    }
    if (a.json)
        std::printf("%s\n", j.dump(2).c_str());
    else if (f.end)
        print_end(f);
    else
        std::printf("%s",
                    fmt::format("{} evaluations so far; the search has not ended\n", seen).c_str());
    return control.stop.load() ? 130 : 0;
}

} // namespace

void register_follow(CLI::App& app, const GlobalOptions&, std::function<int()>& run) {
    auto* cmd = app.add_subcommand(
        "follow", "Follow a search's progress from its --out folder (a cluster job's, or any "
                  "fird optimize's) until it ends");
    auto a = std::make_shared<FollowArgs>();
    cmd->add_option("DIR", a->dir, "The search's --out folder (a job folder before it begins)")
        ->required();
    cmd->add_flag("--once", a->once, "Read the folder once, print where the search is, and end");
    cmd->add_option("--interval", a->interval_s, "Seconds between reads (default 2)")
        ->check(finite_range(0.01, 3600.0));
    cmd->add_option("--idle-timeout", a->idle_timeout_s,
                    "End with an error after this many seconds without a new row, or without "
                    "the search beginning (default 3600)")
        ->check(finite_range(0.01, 1e7));
    cmd->add_flag("--json", a->json, "Print one JSON object when it ends (or with --once)");
    cmd->add_option("--out", a->out, "Write follow.json and progress.png here when it ends");
    cmd->callback([&run, a] { run = [a] { return run_follow(*a); }; });
}

} // namespace fird::app
