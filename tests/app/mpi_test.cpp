// fird optimize across the ranks of an MPI job (mpirun --oversubscribe -np 3 on this
// machine's one device) against the same command in one process: each candidate's rays
// depend on its stage and seed only, so the history, the best reflector and the final l2
// must be the very same numbers, not merely close. And the faults: a rank that dies or
// hangs ends the run with one line naming it, and --resume on one rank ends where an
// uninterrupted run ends. Registered only in a build with MPI (FIRD_BUILD_MPI).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_fird.hpp"

namespace {

using fird::test::Result;
using fird::test::run_fird;

const std::string kMirror = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
const std::string kFreeform = std::string(FIRD_SOURCE_DIR) + "/scenes/test/freeform_search.toml";

// Open MPI refuses root without these (CI runs as root in a container); the shared-memory
// transport's single-copy mechanism needs ptrace rights a container may not grant.
const std::string kMpiEnv = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
                            "OMPI_MCA_btl_vader_single_copy_mechanism=none";

Result one_process(const std::string& args) {
    return run_fird("timeout 120", args);
}

Result ranks(int n, const std::string& args, const std::string& env = "") {
    return run_fird(kMpiEnv + " " + env + " timeout 120 " + FIRD_MPIEXEC + " --oversubscribe -np " +
                        std::to_string(n),
                    args);
}

std::string fresh_dir(const std::string& name) {
    const std::string dir = ::testing::TempDir() + "/fird_mpi_" + name;
    std::filesystem::remove_all(dir);
    return dir;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

using fird::test::history_rows;

int error_lines(const std::string& out) {
    int n = 0;
    for (std::size_t at = out.find("fird: error:"); at != std::string::npos;
         at = out.find("fird: error:", at + 1))
        ++n;
    return n;
}

// Two output folders of the same search: the same rows, the same best reflector (its
// parameters, its scene file) and the same final l2 and far field of it.
// `rows`: how many candidates the search must have (0: as many as one process has).
void expect_same_search(const std::string& one, const std::string& many, std::size_t rows) {
    const std::vector<std::string> a = history_rows(one), b = history_rows(many);
    if (rows > 0) {
        EXPECT_EQ(a.size(), rows + 1); // and the header
    }
    EXPECT_GT(a.size(), 2u); // a search, not a header
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k)
        EXPECT_EQ(a[k], b[k]) << "history row " << k;
    const auto ja = nlohmann::json::parse(read_text(one + "/search.json"));
    const auto jb = nlohmann::json::parse(read_text(many + "/search.json"));
    EXPECT_EQ(ja["best_parameters"], jb["best_parameters"]);
    EXPECT_EQ(ja["best_l2"], jb["best_l2"]);
    EXPECT_EQ(ja["final_l2"], jb["final_l2"]);
    EXPECT_EQ(ja["evaluations"], jb["evaluations"]);
    EXPECT_EQ(read_text(one + "/best.toml"), read_text(many + "/best.toml"));
    EXPECT_EQ(read_text(one + "/farfield.npy"), read_text(many + "/farfield.npy"));
}

// The search of `args` in one process and on three ranks, into two folders: the same
// search, the ranks' note counting every traced candidate (some of them on ranks 1 and 2).
void expect_three_ranks_as_one(const std::string& name, const std::string& args, std::size_t rows) {
    const std::string one = fresh_dir(name + "1"), many = fresh_dir(name + "3");
    const Result a = one_process(args + " --out " + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result b = ranks(3, args + " --out " + many);
    ASSERT_EQ(b.code, 0) << b.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        b.out, m,
        std::regex("fird: note: 3 ranks: \\d+ batches, (\\d+) candidates traced on ranks "
                   "1-2 and (\\d+) on rank 0")))
        << b.out;
    EXPECT_GT(std::stoul(m[1]), 0u);
    expect_same_search(one, many, rows);
    // Traced in batches: all a grid's; the points a method asks for alone (a population's
    // lone candidate, auto's refine) on rank 0 outside them.
    EXPECT_LE(std::stoul(m[1]) + std::stoul(m[2]), history_rows(one).size() - 1);
}

TEST(Mpi, GridSearchOnThreeRanksWritesWhatOneProcessWrites) {
    // The 13 x 13 lattice.
    expect_three_ranks_as_one("grid", "optimize " + kMirror + " --method grid", 169);
}

// The job a workbench or `fird optimize --job-script` writes: its run.sh starts the search
// under mpirun (found on PATH, as a user's shell finds it) on the ranks asked for, and the
// search is the one process's.
TEST(Mpi, AJobsRunShOnThreeRanksWritesWhatOneProcessWrites) {
    const std::string one = fresh_dir("job1"), job = fresh_dir("job3");
    const Result a = one_process("optimize " + kMirror + " --method grid --out " + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result w =
        one_process("optimize " + kMirror + " --method grid --out " + job + " --job-script");
    ASSERT_EQ(w.code, 0) << w.out;
    const Result r =
        fird::test::run_shell(kMpiEnv + " MPIRUN_ARGS=--oversubscribe FIRD=" + FIRD_BINARY +
                              " timeout 120 bash " + job + "/run.sh 3");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("fird: note: 3 ranks:"), std::string::npos) << r.out;
    expect_same_search(one, job, 169);
}

// CMA-ES over nine heights (pagmo's generations, each one batch split among the ranks).
TEST(Mpi, PopulationSearchOnThreeRanksWritesWhatOneProcessWrites) {
    expect_three_ranks_as_one("cmaes", "optimize " + kFreeform + " --method cmaes --max-evals 60",
                              60);
}

// auto: its stages' lattice polls (a neighbourhood a batch) split among the ranks.
TEST(Mpi, AutoSearchOnThreeRanksWritesWhatOneProcessWrites) {
    expect_three_ranks_as_one("auto", "optimize " + kMirror, 0);
}

// A search over the source's place: every point has its own source, so a rank sets it for
// each of its points (the rayset made again), as the search does alone.
TEST(Mpi, ASearchThatMovesTheSourceOnThreeRanksWritesWhatOneProcessWrites) {
    std::string text =
        read_text(std::string(FIRD_SOURCE_DIR) + "/scenes/test/focused_paraboloid_search.toml");
    const std::size_t from = text.find("[reflector.optimize]"), to = text.find("[trace]");
    ASSERT_NE(from, std::string::npos);
    ASSERT_NE(to, std::string::npos);
    text.replace(from, to - from,
                 "[reflector.optimize]\nfx = { min = 2.5, max = 4.5, step = 0.5 }\n\n"
                 "[source.optimize]\nx_mm = { min = -1.0, max = 1.0, step = 0.25 }\n\n");
    const std::string scene = ::testing::TempDir() + "/fird_mpi_source.toml";
    std::ofstream(scene) << text;
    // The 5 x 9 lattice of fx and the source's x.
    expect_three_ranks_as_one("source", "optimize " + scene + " --method grid", 45);
}

// fird tolerance: the realisations after the nominal one shared among the ranks (each its
// draws from the seed and its number, a perturbed mesh of its own): the same rows and the
// same spreads as one process.
TEST(Mpi, ToleranceOnThreeRanksWritesWhatOneProcessWrites) {
    const std::string one = fresh_dir("tolerance1"), many = fresh_dir("tolerance3");
    const std::string args = "tolerance " + std::string(FIRD_SOURCE_DIR) +
                             "/scenes/test/focused_paraboloid_search.toml --realisations 4 "
                             "--source-shift-mm 0.2 --reflectance-sd 0.02 --surface-rms-mm 0.05 "
                             "--surface-correlation-mm 5 --rays 2e4 --out ";
    const Result a = one_process(args + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result b = ranks(3, args + many);
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_NE(b.out.find("realisations traced on ranks 1-2"), std::string::npos) << b.out;
    // The nominal, then 4 joint and 4 for each of the three tolerances: 17 rows and a header.
    const std::string csv = read_text(one + "/tolerance.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 18);
    EXPECT_EQ(csv, read_text(many + "/tolerance.csv"));
    auto ja = nlohmann::json::parse(read_text(one + "/tolerance.json"));
    auto jb = nlohmann::json::parse(read_text(many + "/tolerance.json"));
    ja.erase("time_s");
    jb.erase("time_s");
    EXPECT_EQ(ja, jb);
}

// fird calibrate semivariogram: each series' points shared among the ranks (each point's
// rays follow from its place in the series), the noise replicates and the resolvable step's
// probes on rank 0: the same series, fits and steps as one process, less the times.
TEST(Mpi, SemivariogramOnThreeRanksWritesWhatOneProcessWrites) {
    const std::string one = fresh_dir("semivariogram1"), many = fresh_dir("semivariogram3");
    const std::string args =
        "calibrate semivariogram " + kMirror + " --points 9 --rays 2e4 --json --out ";
    const Result a = one_process(args + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result b = ranks(3, args + many);
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_NE(b.out.find("series points traced on ranks 1-2"), std::string::npos) << b.out;
    // Both parameters' series, 9 points each, a header: the same rows to the last digit.
    const std::string series = read_text(one + "/series.csv");
    EXPECT_EQ(std::count(series.begin(), series.end(), '\n'), 1 + 2 * 9) << series;
    EXPECT_EQ(series, read_text(many + "/series.csv"));
    EXPECT_EQ(read_text(one + "/semivariogram.csv"), read_text(many + "/semivariogram.csv"));
    auto ja = nlohmann::json::parse(a.out.substr(a.out.find('{')));
    auto jb = nlohmann::json::parse(b.out.substr(b.out.find('{')));
    for (auto* j : {&ja, &jb}) {
        j->erase("time_s");
        for (auto& p : (*j)["parameters"])
            p.erase("time_s");
    }
    EXPECT_EQ(ja, jb);
}

// A CSV file's rows as name -> text, by its header.
std::vector<std::map<std::string, std::string>> csv_by_name(const std::string& path) {
    std::istringstream in(read_text(path));
    std::vector<std::map<std::string, std::string>> rows;
    std::vector<std::string> header;
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::istringstream cs(line);
        for (std::string cell; std::getline(cs, cell, ',');)
            cells.push_back(cell);
        if (header.empty()) {
            header = cells;
            continue;
        }
        if (line.empty()) continue;
        EXPECT_EQ(cells.size() + (line.back() == ',' ? 1 : 0), header.size()) << line;
        std::map<std::string, std::string> row;
        for (std::size_t k = 0; k < cells.size(); ++k)
            row[header[k]] = cells[k];
        rows.push_back(row);
    }
    return rows;
}

// fird bench: the sweep's rows shared among the ranks, each measured on its rank's device:
// the same rows in the same order, with the same rays, effective rays and l2 to the same
// CPU reference (each row's rays depend on the scene and its seed, not on the rank), and
// the rank column saying ranks 1 and 2 measured some; the times are each rank's own.
TEST(Mpi, BenchOnThreeRanksMeasuresTheRowsOneProcessMeasures) {
    const std::string one = fresh_dir("bench1"), many = fresh_dir("bench3");
    const std::string args = "bench " + std::string(FIRD_SOURCE_DIR) +
                             "/scenes/test/flat_mirror.toml " + kMirror +
                             " --heightfields 40x40,61x37 --rays 2e4 --reference-rays 1e5 --out ";
    const Result a = one_process(args + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result b = ranks(3, args + many);
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_NE(b.out.find("fird: note: 3 ranks: 1 batches, "), std::string::npos) << b.out;
    // Each rank's device: here the same one on all three.
    EXPECT_NE(b.out.find(", on each of 3 ranks"), std::string::npos) << b.out;
    const auto ra = csv_by_name(one + "/bench.csv"), rb = csv_by_name(many + "/bench.csv");
    ASSERT_EQ(ra.size(), 8u); // 2 scenes x 2 height fields x 2 hit modes
    ASSERT_EQ(rb.size(), ra.size());
    std::set<std::string> measured_on;
    for (std::size_t k = 0; k < ra.size(); ++k) {
        for (const char* same : {"scene", "heightfield_w", "heightfield_h", "rays", "effective",
                                 "mode", "l2_lm", "noise_lm", "aborted", "noise_from"})
            EXPECT_EQ(ra[k].at(same), rb[k].at(same)) << "row " << k << ": " << same;
        EXPECT_EQ(ra[k].at("rank"), "0");
        measured_on.insert(rb[k].at("rank"));
    }
    EXPECT_EQ(measured_on, (std::set<std::string>{"0", "1", "2"}));
}

// fird bench --candidates: one scene a rank, the rows in the scenes' order.
TEST(Mpi, CandidateBenchOnThreeRanksMeasuresEachSceneOnARank) {
    const std::string many = fresh_dir("candidates3");
    const std::string dir = std::string(FIRD_SOURCE_DIR) + "/scenes/test/";
    const Result b = ranks(3, "bench --candidates " + dir + "flat_mirror.toml " + kMirror + " " +
                                  kFreeform + " --rays 2e4 --reps 2 --batch 1 --out " + many);
    ASSERT_EQ(b.code, 0) << b.out;
    const auto rows = csv_by_name(many + "/candidates.csv");
    ASSERT_EQ(rows.size(), 3u);
    for (std::size_t k = 0; k < rows.size(); ++k) {
        EXPECT_EQ(rows[k].at("rank"), std::to_string(k)) << "scene " << k << " on rank " << k;
        EXPECT_EQ(rows[k].at("rays"), "20000");
    }
}

// fird calibrate rays (Table 1): each row's runs shared among the ranks in pairs (the
// replicate estimate needs a pair's two far fields), summed in the runs' order on rank 0:
// the same table as one process, less the rows' times.
TEST(Mpi, TableOneOnThreeRanksWritesWhatOneProcessWrites) {
    const std::string one = fresh_dir("table1_1"), many = fresh_dir("table1_3");
    const std::string args =
        "calibrate rays " + kMirror + " --counts 1e3,1e4 --runs 7 --json --out ";
    const Result a = one_process(args + one);
    ASSERT_EQ(a.code, 0) << a.out;
    const Result b = ranks(3, args + many);
    ASSERT_EQ(b.code, 0) << b.out;
    EXPECT_NE(b.out.find("pairs of runs traced on ranks 1-2"), std::string::npos) << b.out;
    auto ja = nlohmann::json::parse(a.out.substr(a.out.find('{')));
    auto jb = nlohmann::json::parse(b.out.substr(b.out.find('{')));
    ASSERT_EQ(ja["rows"].size(), 2u);
    ASSERT_EQ(jb["rows"].size(), 2u);
    for (auto* j : {&ja, &jb}) {
        j->erase("time_s");
        for (auto& row : (*j)["rows"])
            row.erase("time_s");
    }
    EXPECT_EQ(ja["rows"][0]["replicate_pairs"], 3); // runs (0, 1), (2, 3), (4, 5); 6 alone
    EXPECT_EQ(ja, jb);
}

// The last rank exits (code 3) after two shares (of 16 candidates each): mpirun ends the
// job (SIGTERM to rank 0, then SIGKILL). Rank 0 stops waiting, names the rank it waited on
// and leaves its history; --resume in one process traces the rest and ends as an
// uninterrupted search.
TEST(Mpi, ARankThatDiesEndsTheRunAndResumeOnOneProcessEndsAsUninterrupted) {
    const std::string whole = fresh_dir("whole"), cut = fresh_dir("died");
    const Result w = one_process("optimize " + kMirror + " --method grid --out " + whole);
    ASSERT_EQ(w.code, 0) << w.out;
    const Result r = ranks(3, "optimize " + kMirror + " --method grid --out " + cut,
                           "FIRD_TEST_RANK_EXIT_AFTER=2");
    EXPECT_NE(r.code, 0) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    // The ranks it waited on when mpirun stopped it: rank 2 among them (rank 1 too, when
    // it had not answered yet).
    const std::size_t line = r.out.find("fird: error: the run was stopped");
    ASSERT_NE(line, std::string::npos) << r.out;
    const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
    EXPECT_TRUE(text.find("waited on rank 2;") != std::string::npos ||
                text.find("waited on rank 1, 2;") != std::string::npos)
        << text;
    EXPECT_NE(text.find(cut + "/history.csv keeps the candidates so far: fird optimize " + kMirror +
                        " --resume " + cut + " continues"),
              std::string::npos)
        << text;
    const std::size_t kept = history_rows(cut).size();
    EXPECT_GT(kept, 1u);
    EXPECT_LT(kept, 170u);
    const Result resumed = one_process("optimize " + kMirror + " --resume " + cut);
    ASSERT_EQ(resumed.code, 0) << resumed.out;
    expect_same_search(whole, cut, 169);
}

// The last rank stops answering after two shares: rank 0's bounded wait ends the run. The
// bound, 20 s, must exceed what a rank that answers takes for a share, its first one
// (pipelines, rayset, the desired far field) included, on the slowest build the suite runs
// (ASan + UBSan on lavapipe: over 2 s).
TEST(Mpi, ARankThatHangsEndsTheRunAfterTheRankTimeout) {
    const std::string cut = fresh_dir("hung");
    const Result r =
        ranks(3, "optimize " + kMirror + " --method grid --rank-timeout 20 --out " + cut,
              "FIRD_TEST_RANK_HANG_AFTER=2");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird: error: rank 2 did not answer within 20 s (--rank-timeout)"),
              std::string::npos)
        << r.out;
    EXPECT_GT(history_rows(cut).size(), 1u);
}

// Bad input under mpirun: one line from rank 0, exit 2.
TEST(Mpi, BadOptionsAreOneLineUsageErrors) {
    Result r = ranks(2, "optimize " + kMirror + " --rank-timeout 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird: error: --rank-timeout must be more than 0 s"), std::string::npos)
        << r.out;
    r = ranks(2, "trace " + kMirror);
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird trace runs in one process"), std::string::npos) << r.out;
    r = ranks(2, "calibrate semivariogram " + kMirror + " --rank-timeout 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird: error: --rank-timeout must be more than 0 s"), std::string::npos)
        << r.out;
    r = ranks(2, "stress");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird stress runs in one process"), std::string::npos) << r.out;
    r = ranks(2, "bench " + kMirror + " --rank-timeout 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_EQ(error_lines(r.out), 1) << r.out;
    EXPECT_NE(r.out.find("fird: error: --rank-timeout must be more than 0 s"), std::string::npos)
        << r.out;
    // In one process the option is checked the same way.
    r = one_process("optimize " + kMirror + " --rank-timeout -1");
    EXPECT_EQ(r.code, 2) << r.out;
}

// srun's tasks that did not join one MPI job (srun --mpi=none: measured on Slurm 22.05, each
// task ran the whole search and wrote the same folder): a command that shares work across
// ranks is refused, one line, exit 2, before anything runs; any other runs in each task.
// SLURM_STEP_NUM_TASKS is what srun sets in each task of a step.
TEST(Mpi, SrunTasksThatDidNotJoinOneJobAreRefused) {
    const std::string out = fresh_dir("unjoined");
    const Result t = run_fird("SLURM_STEP_NUM_TASKS=3 SLURM_PROCID=1 timeout 60",
                              "optimize " + kMirror + " --method grid --out " + out);
    EXPECT_EQ(t.code, 2) << t.out;
    EXPECT_EQ(error_lines(t.out), 1) << t.out;
    EXPECT_NE(t.out.find("fird: error: srun started 3 tasks that did not join one MPI job"),
              std::string::npos)
        << t.out;
    EXPECT_FALSE(std::filesystem::exists(out)) << "nothing written";
    // A command of its own in each task (a wrapper's), and one task of a step (sbatch's
    // own, srun -n 1), run.
    EXPECT_EQ(run_fird("SLURM_STEP_NUM_TASKS=3 SLURM_PROCID=1 timeout 60", "info").code, 0);
    EXPECT_EQ(run_fird("SLURM_STEP_NUM_TASKS=1 SLURM_PROCID=0 timeout 60",
                       "bench --candidates " + kMirror + " --rays 1e4 --reps 1 --batch 1 --out " +
                           fresh_dir("one_task"))
                  .code,
              0);
}

} // namespace
