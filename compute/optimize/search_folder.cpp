#include "search_folder.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/scene_file.hpp"
#include "optimize/parameter_space.hpp"

namespace fird {

namespace {

namespace fs = std::filesystem;

std::string in_dir(const std::string& dir, const char* name) {
    return (fs::path(dir) / name).string();
}

// The whole file, or nothing when it is not there (yet).
std::optional<std::string> read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

nlohmann::json parse_json(const std::string& path, const std::string& text) {
    try {
        return nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
    }
}

std::optional<double> optional_number(const nlohmann::json& j, const char* key) {
    const auto it = j.find(key);
    if (it == j.end() || it->is_null()) return std::nullopt;
    return it->get<double>();
}

SearchEnd search_end(const std::string& path, const nlohmann::json& j) {
    try {
        SearchEnd end;
        end.evaluations = j.at("evaluations").get<std::uint64_t>();
        end.stopped = j.at("stopped").get<std::string>();
        end.time_s = j.at("time_s").get<double>();
        end.start_l2 = optional_number(j, "start_l2");
        end.final_l2 = optional_number(j, "final_l2");
        end.noise_floor_l2 = optional_number(j, "noise_floor_l2");
        if (const auto& b = j.at("best_evaluation"); !b.is_null())
            end.best_evaluation = b.get<std::uint64_t>();
        end.best_parameters = j.at("best_parameters").get<std::map<std::string, double>>();
        return end;
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
    }
}

} // namespace

bool search_began(const std::string& dir) {
    std::error_code ec;
    return fs::is_regular_file(in_dir(dir, "options.json"), ec);
}

FollowedSearch read_search_folder(const std::string& dir) {
    const std::string path = in_dir(dir, "options.json");
    const auto text = read_text(path);
    if (!text)
        throw std::runtime_error(fmt::format(
            "{}: no options.json there (not the --out folder of a search, or its search has "
            "not begun)",
            dir));
    const nlohmann::json j = parse_json(path, *text);
    FollowedSearch f{.dir = dir};
    try {
        f.method = j.at("method").get<std::string>();
        f.max_evaluations = j.at("max_evaluations").get<std::uint64_t>();
        // Its files named as the scene named them: found from the scene's own folder
        // (recorded since 2026-12-04; before, from this folder).
        const std::string scene_path = j.value("scene_path", path);
        try {
            f.scene = parse_scene(j.at("scene").get<std::string>(), scene_path);
        } catch (const std::exception& e) {
            throw std::runtime_error(fmt::format("{}: scene: {}", path, e.what()));
        }
    } catch (const nlohmann::json::exception& e) {
        throw std::runtime_error(fmt::format("{}: {}", path, e.what()));
    }
    const ParameterSpace space = parameter_space(f.scene);
    f.names = space.names;
    f.bounds = space.bounds();
    refresh_search_folder(f);
    return f;
}

void refresh_search_folder(FollowedSearch& f) {
    const std::string history = in_dir(f.dir, "history.csv");
    // search.json first: written after the last row, so rows read after it are all of them.
    const std::string result = in_dir(f.dir, "search.json");
    std::optional<SearchEnd> end;
    if (const auto text = read_text(result)) end = search_end(result, parse_json(result, *text));
    // (A header still being written is no rows yet.)
    if (const auto text = read_text(history); text && text->find('\n') != std::string::npos)
        f.rows = parse_history(*text, history, f.names, f.scene.optimize);
    // A resumed search removes the end it continues; one read before that, beside rows
    // written since, is not this search's end.
    f.end = end && end->evaluations == f.rows.candidates.size() ? end : std::nullopt;
}

SearchResult followed_result(const FollowedSearch& f) {
    SearchResult r;
    r.method = f.method;
    r.names = f.names;
    r.bounds = f.bounds;
    r.history = f.rows.candidates;
    r.stages = f.rows.stages;
    r.metric = metric_name(f.scene.optimize.metric);
    r.metric_unit = metric_unit(f.scene.optimize.metric);
    for (const Candidate& c : r.history)
        r.infeasible += c.feasible ? 0 : 1;
    if (const Candidate* best = latest_stage_best(r.history)) {
        r.best = best->index;
        r.best_l2_lm = best->l2_lm;
        r.best_score = best->score;
        for (std::size_t k = 0; k < f.names.size(); ++k)
            r.best_parameters[f.names[k]] = best->x[k];
    }
    if (f.end) {
        for (StopReason reason :
             {StopReason::None, StopReason::Threshold, StopReason::Converged,
              StopReason::MaxEvaluations, StopReason::Exhausted, StopReason::Interrupted})
            if (f.end->stopped == stop_reason_name(reason)) r.stopped = reason;
        r.time_s = f.end->time_s;
        r.start_l2_lm = f.end->start_l2;
        r.final_l2_lm = f.end->final_l2;
        r.noise_floor_l2_lm = f.end->noise_floor_l2;
        // The search's own account of its best (the same rule; it stands if they differ).
        if (f.end->best_evaluation && *f.end->best_evaluation < r.history.size()) {
            r.best = f.end->best_evaluation;
            r.best_l2_lm = r.history[*r.best].l2_lm;
            r.best_score = r.history[*r.best].score;
        }
        r.best_parameters = f.end->best_parameters;
    }
    return r;
}

nlohmann::json followed_search_json(const FollowedSearch& f) {
    const SearchResult r = followed_result(f);
    const auto optional = [](const std::optional<double>& v) {
        return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
    };
    nlohmann::json stages = nlohmann::json::array();
    for (std::size_t k = 0; k < r.stages.size(); ++k) {
        const StageSummary& s = r.stages[k];
        stages.push_back({{"stage", s.name},
                          {"rays", s.fidelity.rays},
                          {"farfield", {s.fidelity.farfield_w, s.fidelity.farfield_h}},
                          {"evaluations", s.evaluations},
                          {"infeasible", s.infeasible},
                          {"best_l2", s.best ? nlohmann::json(s.best_l2_lm) : nullptr}});
    }
    nlohmann::json best = nullptr;
    if (r.best && *r.best < r.history.size()) {
        const Candidate& c = r.history[*r.best];
        best = {{"evaluation", c.index},
                {"stage", c.stage < r.stages.size() ? r.stages[c.stage].name : std::string()},
                {"l2", c.l2_lm},
                {"score", c.score},
                {"parameters", r.best_parameters}};
    }
    nlohmann::json j = {{"dir", f.dir},
                        {"scene", f.scene.name},
                        {"method", f.method},
                        {"metric", r.metric},
                        {"metric_unit", r.metric_unit},
                        {"parameters", f.names},
                        {"max_evaluations", f.max_evaluations},
                        {"evaluations", r.history.size()},
                        {"infeasible", r.infeasible},
                        {"stages", stages},
                        {"best", best},
                        {"ended", f.end.has_value()}};
    if (f.end) {
        j["stopped"] = f.end->stopped;
        j["time_s"] = f.end->time_s;
        j["start_l2"] = optional(f.end->start_l2);
        j["final_l2"] = optional(f.end->final_l2);
        j["noise_floor_l2"] = optional(f.end->noise_floor_l2);
        j["best_parameters"] = f.end->best_parameters;
    }
    return j;
}

const Candidate* latest_stage_best(const std::vector<Candidate>& history) {
    const Candidate* best = nullptr;
    for (const Candidate& c : history)
        if (c.feasible &&
            (!best || c.stage > best->stage || (c.stage == best->stage && c.score < best->score)))
            best = &c;
    return best;
}

} // namespace fird
