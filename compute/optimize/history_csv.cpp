#include "history_csv.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "io/parse_number.hpp"

namespace fird {

namespace {

std::vector<std::string> split(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');)
        cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    return cells;
}

double number(const std::string& path, std::size_t line, const std::string& cell) {
    const auto v = parse_finite_number(cell);
    if (!v) throw std::runtime_error(fmt::format("{}:{}: '{}' is not a number", path, line, cell));
    return *v;
}

} // namespace

std::string history_header(const std::vector<std::string>& names,
                           const OptimizeSettings& optimize) {
    return fmt::format("index,stage,stage_name,rays,farfield_w,farfield_h,{},{}_{}{},feasible,ms",
                       fmt::join(names, ","), metric_name(optimize.metric),
                       metric_unit(optimize.metric),
                       optimize.smoothness > 0.0 ? ",smoothness" : "");
}

HistoryWriter::HistoryWriter(const std::string& path, const std::vector<std::string>& names,
                             bool append, const OptimizeSettings& optimize)
    : path_(path), file_(std::fopen(path.c_str(), append ? "a" : "w")),
      smoothness_(optimize.smoothness > 0.0) {
    if (!file_) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
    if (!append) std::fprintf(file_, "%s\n", history_header(names, optimize).c_str());
    std::fflush(file_);
}

HistoryWriter::~HistoryWriter() {
    if (file_) std::fclose(file_);
}

void HistoryWriter::write(const Candidate& c, const StageSummary& s) {
    if (c.replayed) return; // already in the file
    std::string row = fmt::format("{},{},{},{},{},{}", c.index, c.stage, s.name, s.fidelity.rays,
                                  s.fidelity.farfield_w, s.fidelity.farfield_h);
    for (double v : c.x)
        row += fmt::format(",{:.17g}", v);
    row += c.feasible ? fmt::format(",{:.17g}", c.l2_lm) : std::string(",");
    if (smoothness_) row += c.feasible ? fmt::format(",{:.17g}", c.smoothness) : std::string(",");
    row += fmt::format(",{},{:.3f}\n", c.feasible ? 1 : 0, c.ms);
    // One write and a flush per row: a killed search loses at most the row being written.
    if (std::fputs(row.c_str(), file_) < 0 || std::fflush(file_) != 0)
        throw std::runtime_error(fmt::format("{}: write failed", path_));
}

std::vector<Candidate> read_history(const std::string& path, const std::vector<std::string>& names,
                                    const OptimizeSettings& optimize) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
    std::stringstream ss;
    ss << in.rdbuf();
    in.close();
    const std::string text = ss.str();
    HistoryRows rows = parse_history(text, path, names, optimize);
    // A row cut short: dropped here and in the file the resumed search appends to.
    if (rows.bytes != text.size()) std::filesystem::resize_file(path, rows.bytes);
    return std::move(rows.candidates);
}

HistoryRows parse_history(const std::string& all, const std::string& path,
                          const std::vector<std::string>& names, const OptimizeSettings& optimize) {
    const std::size_t whole = all.rfind('\n');
    if (whole == std::string::npos)
        throw std::runtime_error(fmt::format("{}: no header line", path));
    HistoryRows out;
    out.bytes = whole + 1;
    std::stringstream lines(all.substr(0, out.bytes));
    std::string line;
    std::getline(lines, line);
    const bool smoothness = optimize.smoothness > 0.0;
    if (line != history_header(names, optimize))
        throw std::runtime_error(fmt::format(
            "{}:1: the header does not match this search's parameters ({}), metric ({}) and "
            "smoothness penalty ({})",
            path, fmt::join(names, ", "), metric_name(optimize.metric),
            smoothness ? "weighted" : "none"));
    // The columns after the parameters: the metric, the smoothness, feasible, ms.
    const std::size_t metric_at = 6 + names.size(), feasible_at = metric_at + 1 + smoothness;
    const std::size_t columns = feasible_at + 2;
    std::vector<Candidate>& candidates = out.candidates;
    for (std::size_t n = 2; std::getline(lines, line); ++n) {
        const auto cells = split(line);
        if (cells.size() != columns)
            throw std::runtime_error(
                fmt::format("{}:{}: {} columns, expected {}", path, n, cells.size(), columns));
        Candidate c;
        c.index = std::uint64_t(number(path, n, cells[0]));
        if (c.index != candidates.size())
            throw std::runtime_error(fmt::format("{}:{}: index {} out of order", path, n, c.index));
        const double stage = number(path, n, cells[1]);
        // Stages run in order (one may pass without a candidate: the number then skips it).
        if (!(stage >= 0 && stage == std::floor(stage) && stage < 1e6) ||
            stage + 1 < double(out.stages.size()))
            throw std::runtime_error(
                fmt::format("{}:{}: stage {} out of order", path, n, cells[1]));
        c.stage = std::uint32_t(stage);
        for (std::size_t k = 0; k < names.size(); ++k)
            c.x.push_back(number(path, n, cells[6 + k]));
        const std::string& feasible = cells[feasible_at];
        if (feasible != "0" && feasible != "1")
            throw std::runtime_error(fmt::format("{}:{}: feasible must be 0 or 1", path, n));
        c.feasible = feasible == "1";
        constexpr double nan = std::numeric_limits<double>::quiet_NaN();
        c.l2_lm = c.feasible ? number(path, n, cells[metric_at]) : nan;
        c.smoothness = !c.feasible ? nan : smoothness ? number(path, n, cells[metric_at + 1]) : 0.0;
        c.score = candidate_score(c.l2_lm, c.smoothness, optimize);
        c.ms = number(path, n, cells[feasible_at + 1]);
        c.replayed = true;
        if (c.stage > out.stages.size()) out.stages.resize(c.stage); // passed by, unnamed
        if (c.stage == out.stages.size()) {
            StageSummary s;
            s.name = cells[2];
            s.fidelity.rays = std::uint64_t(number(path, n, cells[3]));
            s.fidelity.farfield_w = std::uint32_t(number(path, n, cells[4]));
            s.fidelity.farfield_h = std::uint32_t(number(path, n, cells[5]));
            out.stages.push_back(std::move(s));
        }
        StageSummary& s = out.stages[c.stage];
        ++s.evaluations;
        s.infeasible += c.feasible ? 0 : 1;
        if (c.feasible && (!s.best || c.score < s.best_score)) {
            s.best = c.index;
            s.best_l2_lm = c.l2_lm;
            s.best_score = c.score;
        }
        candidates.push_back(std::move(c));
    }
    return out;
}

} // namespace fird
