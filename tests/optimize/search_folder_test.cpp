// Reading a search's history from outside (optimize/search_folder.hpp, history_csv.hpp) and
// the words a cluster job's scripts are made of (optimize/cluster_job.hpp): stages counted
// from the rows as the search counted them, a row being written left out, the quoting bash
// itself reads back, and the launcher's time forms.
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include <gtest/gtest.h>

#include "optimize/cluster_job.hpp"
#include "optimize/history_csv.hpp"
#include "optimize/search_folder.hpp"

namespace fird {
namespace {

std::string read_all(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    std::string text;
    for (int c; f && (c = std::fgetc(f)) != EOF;)
        text += char(c);
    if (f) std::fclose(f);
    return text;
}

// Two stages of a smoothness-weighted search, written by the search's own writer: the rows
// below are the answer (their counts and the best by score, which is not the best by l2).
std::string two_stage_history(const OptimizeSettings& optimize) {
    // A file per test: ctest runs them at once.
    const std::string path = ::testing::TempDir() + "/fird_two_stages_" +
                             ::testing::UnitTest::GetInstance()->current_test_info()->name() +
                             ".csv";
    {
        HistoryWriter w(path, {"a", "b"}, false, optimize);
        StageSummary coarse{.name = "coarse",
                            .fidelity = {.rays = 1000, .farfield_w = 36, .farfield_h = 18}};
        StageSummary fine{.name = "fine",
                          .fidelity = {.rays = 100000, .farfield_w = 180, .farfield_h = 90}};
        const auto candidate = [](std::uint64_t i, std::uint32_t stage, double l2, double energy,
                                  bool feasible) {
            return Candidate{.index = i,
                             .stage = stage,
                             .x = {double(i), -double(i)},
                             .feasible = feasible,
                             .l2_lm = l2,
                             .smoothness = energy};
        };
        w.write(candidate(0, 0, 5.0, 1.0, true), coarse);  // score 5 + 2 x 1 = 7
        w.write(candidate(1, 0, 4.0, 3.0, true), coarse);  // 10: lower l2, higher score
        w.write(candidate(2, 0, 0.0, 0.0, false), coarse); // infeasible
        w.write(candidate(3, 1, 2.0, 2.0, true), fine);    // 6
        w.write(candidate(4, 1, 3.0, 0.5, true), fine);    // 4: the fine stage's best
    }
    return read_all(path);
}

TEST(HistoryRows, StagesAreCountedFromTheRowsAndTheBestIsByScore) {
    OptimizeSettings optimize;
    optimize.smoothness = 2.0;
    const std::string text = two_stage_history(optimize);
    const HistoryRows rows = parse_history(text, "h.csv", {"a", "b"}, optimize);
    ASSERT_EQ(rows.candidates.size(), 5u);
    EXPECT_EQ(rows.bytes, text.size());
    ASSERT_EQ(rows.stages.size(), 2u);
    EXPECT_EQ(rows.stages[0].name, "coarse");
    EXPECT_EQ(rows.stages[0].fidelity.rays, 1000u);
    EXPECT_EQ(rows.stages[0].fidelity.farfield_w, 36u);
    EXPECT_EQ(rows.stages[0].evaluations, 3u);
    EXPECT_EQ(rows.stages[0].infeasible, 1u);
    EXPECT_EQ(rows.stages[0].best, 0u);
    EXPECT_EQ(rows.stages[0].best_score, 7.0);
    EXPECT_EQ(rows.stages[1].name, "fine");
    EXPECT_EQ(rows.stages[1].fidelity.farfield_h, 90u);
    EXPECT_EQ(rows.stages[1].best, 4u);
    EXPECT_EQ(rows.stages[1].best_l2_lm, 3.0);
    // The search's rule for its result: the latest stage's best, by score.
    const Candidate* best = latest_stage_best(rows.candidates);
    ASSERT_NE(best, nullptr);
    EXPECT_EQ(best->index, 4u);
}

TEST(HistoryRows, ARowBeingWrittenIsLeftOut) {
    OptimizeSettings optimize;
    optimize.smoothness = 2.0;
    const std::string text = two_stage_history(optimize);
    const std::size_t last_row = text.rfind('\n', text.size() - 2) + 1;
    const std::string cut = text.substr(0, last_row + 5); // five bytes of the last row
    const HistoryRows rows = parse_history(cut, "h.csv", {"a", "b"}, optimize);
    EXPECT_EQ(rows.candidates.size(), 4u);
    EXPECT_EQ(rows.bytes, last_row);
    EXPECT_EQ(rows.stages[1].best, 3u);
}

TEST(HistoryRows, AStageOutOfOrderOrAForeignHeaderIsNamed) {
    OptimizeSettings optimize;
    optimize.smoothness = 2.0;
    std::string text = two_stage_history(optimize);
    // The last row's stage 1 made 0 after stage 1 began.
    const std::size_t last_row = text.rfind('\n', text.size() - 2) + 1;
    text[text.find(',', last_row) + 1] = '0';
    try {
        (void)parse_history(text, "h.csv", {"a", "b"}, optimize);
        FAIL() << "accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "h.csv:6: stage 0 out of order");
    }
    EXPECT_THROW((void)parse_history(text, "h.csv", {"a", "c"}, optimize), std::runtime_error);
    EXPECT_THROW((void)parse_history("no newline", "h.csv", {"a"}, {}), std::runtime_error);
}

// What bash itself reads back from a quoted word.
std::string bash_reads(const std::string& quoted) {
    const std::string line = "bash -c " + shell_quoted("printf %s " + quoted);
    std::FILE* pipe = popen(line.c_str(), "r");
    std::string out;
    for (int c; pipe && (c = std::fgetc(pipe)) != EOF;)
        out += char(c);
    if (pipe) {
        EXPECT_EQ(pclose(pipe), 0) << line;
    }
    return out;
}

TEST(ClusterJobWords, BashReadsAQuotedWordBackAsItWas) {
    for (const std::string word : {"plain", "two words", "it's", "$HOME and `x`", "a\\b\"c'",
                                   "/runs/model a-job-1", "'", ""})
        EXPECT_EQ(bash_reads(shell_quoted(word)), word) << word;
}

TEST(ClusterJobWords, TheShapeTakesSlurmsTimeFormsAndNamesABadOption) {
    ClusterShape s;
    for (const char* t : {"30", "30:00", "4:00:00", "2-12", "2-12:30", "1-12:00:00"}) {
        s.time_limit = t;
        EXPECT_FALSE(cluster_shape_error(s)) << t;
    }
    for (const char* t : {"", "4h", "1:2:3:4", "-1", "1-"}) {
        s.time_limit = t;
        const auto why = cluster_shape_error(s);
        ASSERT_TRUE(why) << t;
        EXPECT_EQ(why->rfind("--time-limit: ", 0), 0u) << *why;
    }
    s = {};
    s.partition = "gpu;rm";
    EXPECT_EQ(cluster_shape_error(s)->rfind("--partition: ", 0), 0u);
    s = {};
    s.gpus_per_node = 0;
    EXPECT_EQ(cluster_shape_error(s)->rfind("--gpus-per-node: ", 0), 0u);
    s = {};
    s.nodes = 0;
    EXPECT_EQ(cluster_shape_error(s)->rfind("--nodes: ", 0), 0u);
}

} // namespace
} // namespace fird
