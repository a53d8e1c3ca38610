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

std::string history_header(const std::vector<std::string>& names, FarFieldMetric metric) {
    return fmt::format("index,stage,stage_name,rays,farfield_w,farfield_h,{},{}_{},feasible,ms",
                       fmt::join(names, ","), metric_name(metric), metric_unit(metric));
}

HistoryWriter::HistoryWriter(const std::string& path, const std::vector<std::string>& names,
                             bool append, FarFieldMetric metric)
    : path_(path), file_(std::fopen(path.c_str(), append ? "a" : "w")) {
    if (!file_) throw std::runtime_error(fmt::format("{}: cannot open for writing", path));
    if (!append) std::fprintf(file_, "%s\n", history_header(names, metric).c_str());
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
    row += c.feasible ? fmt::format(",{:.17g},1", c.l2_lm) : std::string(",,0");
    row += fmt::format(",{:.3f}\n", c.ms);
    // One write and a flush per row: a killed search loses at most the row being written.
    if (std::fputs(row.c_str(), file_) < 0 || std::fflush(file_) != 0)
        throw std::runtime_error(fmt::format("{}: write failed", path_));
}

std::vector<Candidate> read_history(const std::string& path, const std::vector<std::string>& names,
                                    FarFieldMetric metric) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open", path));
    std::stringstream ss;
    ss << in.rdbuf();
    std::string text = ss.str();
    const std::size_t whole = text.rfind('\n');
    if (whole == std::string::npos)
        throw std::runtime_error(fmt::format("{}: no header line", path));
    if (whole + 1 != text.size()) {
        // A row cut short: drop it, here and in the file the resumed search appends to.
        text.resize(whole + 1);
        in.close();
        std::filesystem::resize_file(path, text.size());
    }
    std::stringstream lines(text);
    std::string line;
    std::getline(lines, line);
    if (line != history_header(names, metric))
        throw std::runtime_error(fmt::format(
            "{}:1: the header does not match this search's parameters ({}) and metric ({})", path,
            fmt::join(names, ", "), metric_name(metric)));
    const std::size_t columns = 9 + names.size();
    std::vector<Candidate> out;
    for (std::size_t n = 2; std::getline(lines, line); ++n) {
        const auto cells = split(line);
        if (cells.size() != columns)
            throw std::runtime_error(
                fmt::format("{}:{}: {} columns, expected {}", path, n, cells.size(), columns));
        Candidate c;
        c.index = std::uint64_t(number(path, n, cells[0]));
        if (c.index != out.size())
            throw std::runtime_error(fmt::format("{}:{}: index {} out of order", path, n, c.index));
        c.stage = std::uint32_t(number(path, n, cells[1]));
        for (std::size_t k = 0; k < names.size(); ++k)
            c.x.push_back(number(path, n, cells[6 + k]));
        const std::string& feasible = cells[7 + names.size()];
        if (feasible != "0" && feasible != "1")
            throw std::runtime_error(fmt::format("{}:{}: feasible must be 0 or 1", path, n));
        c.feasible = feasible == "1";
        c.l2_lm = c.feasible ? number(path, n, cells[6 + names.size()])
                             : std::numeric_limits<double>::quiet_NaN();
        c.ms = number(path, n, cells[8 + names.size()]);
        c.replayed = true;
        out.push_back(std::move(c));
    }
    return out;
}

} // namespace fird
