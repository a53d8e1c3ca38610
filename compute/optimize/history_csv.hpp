// history.csv: every candidate of a search, one row each, flushed as it is evaluated so a
// killed search keeps what it did; read back by --resume.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "optimize/search_types.hpp"

namespace fird {

// Columns: index, stage (its number), stage_name, rays, farfield_w, farfield_h, one per
// parameter (by name), l2_lm (candela_l2_cd under that metric; empty when infeasible),
// smoothness (the bending energy, only with an [optimize] smoothness weight; empty when
// infeasible), feasible (1 or 0), ms. Numbers are
// written with 17 significant digits, so a resumed search reads back the very values.
class HistoryWriter {
  public:
    // Creates the file with its header, or (append) opens an existing one to continue it.
    // `optimize` says the columns: its metric, and a smoothness column with a weight.
    HistoryWriter(const std::string& path, const std::vector<std::string>& names, bool append,
                  const OptimizeSettings& optimize = {});
    ~HistoryWriter();
    HistoryWriter(const HistoryWriter&) = delete;
    HistoryWriter& operator=(const HistoryWriter&) = delete;
    void write(const Candidate& candidate, const StageSummary& stage);

  private:
    std::string path_;
    std::FILE* file_ = nullptr;
    bool smoothness_ = false;
};

std::string history_header(const std::vector<std::string>& names,
                           const OptimizeSettings& optimize = {});

// Reads a history written for these parameter names and settings (each candidate's score
// recomputed from its l2 and smoothness). A last line without its newline (a row cut
// short by a kill) is dropped, and the file truncated to the whole rows.
std::vector<Candidate> read_history(const std::string& path, const std::vector<std::string>& names,
                                    const OptimizeSettings& optimize = {});

// A history's whole rows as candidates, and the stages they name (each stage's name, rays
// and far-field grid from its rows; its evaluations, infeasible count and best by score
// counted from them): what a follower of a running search reads.
struct HistoryRows {
    std::vector<Candidate> candidates;
    std::vector<StageSummary> stages;
    std::size_t bytes = 0; // of the text: the whole rows read (a row being written is not)
};

// Parses history text (`path` names it in errors: "PATH:LINE: ..."); a last line without
// its newline is a row still being written and is left out. The file is never touched.
HistoryRows parse_history(const std::string& text, const std::string& path,
                          const std::vector<std::string>& names,
                          const OptimizeSettings& optimize = {});

} // namespace fird
