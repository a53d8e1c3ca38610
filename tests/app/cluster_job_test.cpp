// A search handed to other machines and followed from its folder (issue 28 item 6):
// `fird optimize --job-script` writes scene.toml, run.sh and slurm.sh; each script, run (with
// a stand-in for Slurm's srun that runs the one rank here), makes the very history a search
// started directly makes. `fird follow` reads a search's folder while it runs and after it
// ended: its account must be search.json's own. Bad folders and options are refused with
// one line.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <sys/wait.h>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "run_fird.hpp"

namespace {

using fird::test::Result;

const std::string kMirror = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";

Result run(const std::string& args) {
    return fird::test::run_fird("timeout 300", args);
}

using fird::test::history_rows;
Result shell(const std::string& line) {
    return fird::test::run_shell(line);
}

std::string fresh_dir(const std::string& name) {
    const std::string dir =
        (std::filesystem::path(::testing::TempDir()) / ("fird_job_" + name)).lexically_normal();
    std::filesystem::remove_all(dir);
    return dir;
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

nlohmann::json read_json(const std::string& path) {
    std::ifstream in(path);
    EXPECT_TRUE(in) << path;
    return nlohmann::json::parse(in);
}

// The mirror scene's grid search run directly: what every job and follower must match (a
// folder per test: ctest runs them at once).
const std::string& direct_search() {
    static const std::string dir = [] {
        const std::string d =
            fresh_dir(std::string("direct_") +
                      ::testing::UnitTest::GetInstance()->current_test_info()->name());
        const auto r = run("optimize " + kMirror + " --method grid --out " + d);
        EXPECT_EQ(r.code, 0) << r.out;
        return d;
    }();
    return dir;
}

TEST(ClusterJob, RunShAndSlurmShRunTheSearchTheDirectCommandRuns) {
    const std::string job = fresh_dir("run_sh");
    const auto w = run("optimize " + kMirror + " --method grid --out " + job +
                       " --job-script --ranks 3 --nodes 2 --gpus-per-node 8 --time-limit "
                       "1-12:00:00 --partition gpu-long --json");
    ASSERT_EQ(w.code, 0) << w.out;
    const auto j = nlohmann::json::parse(w.out.substr(w.out.find('{'))).at("job");
    EXPECT_EQ(j.at("run_sh").get<std::string>(), job + "/run.sh");
    EXPECT_EQ(j.at("slurm_sh").get<std::string>(), job + "/slurm.sh");
    EXPECT_EQ(j.at("mpirun").get<std::string>(), "bash '" + job + "/run.sh' 3");
    EXPECT_EQ(j.at("sbatch").get<std::string>(), "sbatch '" + job + "/slurm.sh'");
    for (const char* script : {"/run.sh", "/slurm.sh"}) {
        struct stat st {};
        ASSERT_EQ(stat((job + script).c_str(), &st), 0);
        EXPECT_TRUE(st.st_mode & S_IXUSR) << script;
    }
    // The batch script asks Slurm for the shape given (its directives read by name).
    const std::string slurm = read_text(job + "/slurm.sh");
    for (const char* line :
         {"#SBATCH --nodes=2\n", "#SBATCH --ntasks-per-node=8\n", "#SBATCH --gpus-per-node=8\n",
          "#SBATCH --time=1-12:00:00\n", "#SBATCH --partition=gpu-long\n"})
        EXPECT_NE(slurm.find(line), std::string::npos) << line;
    // run.sh on one rank (fird alone): the direct search's rows, to the bit.
    const auto r =
        shell("FIRD=" + std::string(FIRD_BINARY) + " timeout 300 bash " + job + "/run.sh 1");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(history_rows(job), history_rows(direct_search()));
    EXPECT_EQ(read_json(job + "/search.json").at("best_parameters"),
              read_json(direct_search() + "/search.json").at("best_parameters"));
    // slurm.sh, with srun stood in for by a script that runs the one rank it is given.
    const std::string batch = fresh_dir("slurm_sh"), bin = fresh_dir("fake_srun");
    ASSERT_EQ(run("optimize " + kMirror + " --method grid --out " + batch + " --job-script").code,
              0);
    std::filesystem::create_directories(bin);
    {
        std::ofstream srun(bin + "/srun");
        srun << "#!/bin/sh\n# srun --mpi=X PROGRAM ARGS...: one task, here\nshift\nexec \"$@\"\n";
    }
    std::filesystem::permissions(bin + "/srun", std::filesystem::perms::owner_all);
    const auto s = shell("PATH=" + bin + ":$PATH FIRD=" + std::string(FIRD_BINARY) +
                         " timeout 300 bash " + batch + "/slurm.sh");
    ASSERT_EQ(s.code, 0) << s.out;
    EXPECT_EQ(history_rows(batch), history_rows(direct_search()));
    // Started again, each continues the search recorded there (--resume): nothing is added.
    const auto again =
        shell("FIRD=" + std::string(FIRD_BINARY) + " timeout 300 bash " + job + "/run.sh 1");
    ASSERT_EQ(again.code, 0) << again.out;
    EXPECT_EQ(history_rows(job), history_rows(direct_search()));
}

// fird's own options given with --job-script go into both scripts before the subcommand,
// on the first start and on a resumed one: a stand-in fird ($FIRD) records the words it
// is started with.
TEST(ClusterJob, FirdsOwnOptionsGoWithTheJob) {
    const std::string job = fresh_dir("global_options"), bin = fresh_dir("record_fird");
    ASSERT_EQ(run("--max-batch-rays 65536 --max-device-memory 300.5 --validation optimize " +
                  kMirror + " --method grid --out " + job + " --job-script")
                  .code,
              0);
    std::filesystem::create_directories(bin);
    {
        std::ofstream fake(bin + "/fird");
        fake << "#!/bin/sh\nprintf '%s\\n' \"$@\" > \"$(dirname \"$0\")/words\"\n";
    }
    std::filesystem::permissions(bin + "/fird", std::filesystem::perms::owner_all);
    const auto words = [&] {
        std::ifstream in(bin + "/words");
        std::vector<std::string> w;
        for (std::string line; std::getline(in, line);)
            w.push_back(line);
        return w;
    };
    const std::vector<std::string> global{
        "--validation", "--max-device-memory", "300.5", "--max-batch-rays", "65536",
        "optimize",     job + "/scene.toml"};
    ASSERT_EQ(shell("FIRD=" + bin + "/fird bash " + job + "/run.sh 1").code, 0);
    auto w = words();
    ASSERT_GE(w.size(), global.size());
    EXPECT_EQ(std::vector<std::string>(w.begin(), w.begin() + std::ptrdiff_t(global.size())),
              global);
    EXPECT_EQ(w.at(global.size()), "--out");
    // Once the search has begun (its options.json), the same options with --resume.
    std::ofstream(job + "/options.json") << "{}";
    ASSERT_EQ(shell("FIRD=" + bin + "/fird bash " + job + "/run.sh 1").code, 0);
    w = words();
    ASSERT_GE(w.size(), global.size());
    EXPECT_EQ(std::vector<std::string>(w.begin(), w.begin() + std::ptrdiff_t(global.size())),
              global);
    EXPECT_EQ(w.at(global.size()), "--resume");
}

TEST(ClusterJob, TheJobsSceneIsTheSceneWithItsFilesFoundFromAnywhere) {
    // A scene naming a file by a relative path (an IES target beside it): the job's
    // scene.toml names it absolutely, so the job reads the same file from its own folder.
    const std::string job = fresh_dir("ies_scene");
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/model_a_ies.toml";
    ASSERT_TRUE(std::filesystem::exists(scene));
    const auto w = run("optimize " + scene + " --out " + job + " --job-script");
    ASSERT_EQ(w.code, 0) << w.out;
    const std::string text = read_text(job + "/scene.toml");
    const auto file = text.find("file = '");
    ASSERT_NE(file, std::string::npos) << text;
    EXPECT_EQ(text[file + 8], '/') << text.substr(file, 80);
    // And it reads from the job's folder: a trace at a few rays reads every file it names.
    const auto t = run("trace " + job + "/scene.toml --rays 1000 --json");
    EXPECT_EQ(t.code, 0) << t.out;
}

TEST(Follow, FollowsARunningSearchToItsEndAndReportsWhatSearchJsonStates) {
    const std::string dir = fresh_dir("followed"), out = fresh_dir("follow_out");
    std::filesystem::create_directories(dir); // a job folder: there before its search begins
    // The search starts a second after the follower, in the background.
    const auto r = shell("(sleep 1; " + std::string(FIRD_BINARY) + " optimize " + kMirror +
                         " --method grid --out " + dir + " >/dev/null 2>&1) & " + "timeout 300 " +
                         FIRD_BINARY + " follow " + dir + " --interval 0.05 --json --out " + out +
                         "; code=$?; wait; exit $code");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    const auto search = read_json(dir + "/search.json");
    EXPECT_TRUE(j.at("ended").get<bool>());
    EXPECT_EQ(j.at("evaluations"), search.at("evaluations"));
    EXPECT_EQ(j.at("best_parameters"), search.at("best_parameters"));
    EXPECT_EQ(j.at("best").at("evaluation"), search.at("best_evaluation"));
    EXPECT_EQ(j.at("best").at("l2"), search.at("best_l2"));
    EXPECT_EQ(j.at("final_l2"), search.at("final_l2"));
    EXPECT_EQ(j.at("stopped"), search.at("stopped"));
    EXPECT_EQ(j.at("parameters"), nlohmann::json({"sx", "sy"}));
    ASSERT_EQ(j.at("stages").size(), 1u);
    EXPECT_EQ(j.at("stages").at(0).at("evaluations"), search.at("evaluations"));
    EXPECT_EQ(read_json(out + "/follow.json"), j);
    EXPECT_TRUE(std::filesystem::file_size(out + "/progress.png") > 1000);
    // Read once after its end, in words: its stop and best.
    const auto once = run("follow " + dir + " --once");
    ASSERT_EQ(once.code, 0) << once.out;
    EXPECT_NE(once.out.find("stopped: exhausted"), std::string::npos) << once.out;
    EXPECT_NE(once.out.find("best: sx=0.15 sy=-0.1"), std::string::npos) << once.out;
}

TEST(Follow, ARowBeingWrittenIsLeftOutAndTheFileIsNotTouched) {
    // A search's folder copied mid-row: the follower reads the whole rows and leaves the
    // file as it found it (the running search appends to it).
    const std::string dir = fresh_dir("mid_row");
    std::filesystem::create_directories(dir);
    std::filesystem::copy_file(direct_search() + "/options.json", dir + "/options.json");
    const std::string history = read_text(direct_search() + "/history.csv");
    const std::size_t cut = history.find('\n', history.size() / 2) + 12; // into a row
    {
        std::ofstream h(dir + "/history.csv", std::ios::binary);
        h << history.substr(0, cut);
    }
    const auto r = run("follow " + dir + " --once --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    const auto whole_rows = std::count(history.begin(), history.begin() + long(cut), '\n') - 1;
    EXPECT_EQ(j.at("evaluations").get<long>(), whole_rows);
    EXPECT_FALSE(j.at("ended").get<bool>());
    EXPECT_EQ(std::filesystem::file_size(dir + "/history.csv"), cut);
}

TEST(Follow, BadFoldersAndOptionsAreRefusedWithOneLine) {
    const std::string empty = fresh_dir("empty");
    std::filesystem::create_directories(empty);
    const auto missing = run("follow " + empty + "/nowhere");
    EXPECT_EQ(missing.code, 1);
    EXPECT_NE(missing.out.find("no such folder"), std::string::npos) << missing.out;
    const auto not_begun = run("follow " + empty + " --once");
    EXPECT_EQ(not_begun.code, 1);
    EXPECT_NE(not_begun.out.find("no search has begun there"), std::string::npos) << not_begun.out;
    const auto idle = run("follow " + empty + " --interval 0.05 --idle-timeout 0.3");
    EXPECT_EQ(idle.code, 1);
    EXPECT_NE(idle.out.find("--idle-timeout"), std::string::npos) << idle.out;
    // A history whose header is not its search's: the file and line named.
    const std::string broken = fresh_dir("broken");
    std::filesystem::create_directories(broken);
    std::filesystem::copy_file(direct_search() + "/options.json", broken + "/options.json");
    {
        std::ofstream h(broken + "/history.csv");
        h << "index,stage,something,else\n";
    }
    const auto b = run("follow " + broken + " --once");
    EXPECT_EQ(b.code, 1);
    EXPECT_NE(b.out.find(broken + "/history.csv:1:"), std::string::npos) << b.out;
    {
        std::ofstream o(broken + "/options.json");
        o << "{\"method\": \"grid\"";
    }
    const auto o = run("follow " + broken + " --once");
    EXPECT_EQ(o.code, 1);
    EXPECT_NE(o.out.find(broken + "/options.json"), std::string::npos) << o.out;
    EXPECT_EQ(run("follow " + empty + " --interval nan").code, 2);
    EXPECT_EQ(run("follow").code, 2);
}

TEST(ClusterJob, BadShapesAndOptionsAreRefusedNamingTheOption) {
    const std::string job = fresh_dir("bad");
    const auto no_out = run("optimize " + kMirror + " --job-script");
    EXPECT_EQ(no_out.code, 2);
    EXPECT_NE(no_out.out.find("--job-script needs --out"), std::string::npos) << no_out.out;
    const auto alone = run("optimize " + kMirror + " --nodes 2 --out " + job);
    EXPECT_EQ(alone.code, 2);
    EXPECT_NE(alone.out.find("--nodes goes with --job-script"), std::string::npos) << alone.out;
    const auto time =
        run("optimize " + kMirror + " --job-script --out " + job + " --time-limit 4h");
    EXPECT_EQ(time.code, 2);
    EXPECT_NE(time.out.find("--time-limit: '4h'"), std::string::npos) << time.out;
    const auto part =
        run("optimize " + kMirror + " --job-script --out " + job + " --partition 'a b'");
    EXPECT_EQ(part.code, 2);
    EXPECT_NE(part.out.find("--partition"), std::string::npos) << part.out;
    EXPECT_EQ(run("optimize " + kMirror + " --job-script --out " + job + " --ranks 0").code, 2);
    // Options a search would refuse are refused when the job is written, not on the cluster.
    const auto refine =
        run("optimize " + kMirror + " --job-script --out " + job + " --method cmaes --refine");
    EXPECT_EQ(refine.code, 2);
    EXPECT_NE(refine.out.find("--refine"), std::string::npos) << refine.out;
    EXPECT_FALSE(std::filesystem::exists(job + "/run.sh"));
    // A folder where a search has begun keeps it: its own scripts continue it.
    const auto taken = run("optimize " + kMirror + " --job-script --out " + direct_search());
    EXPECT_EQ(taken.code, 1);
    EXPECT_NE(taken.out.find("a search has begun here already"), std::string::npos) << taken.out;
}

// A search stopped (SIGTERM: its search.json says "interrupted") and resumed in its folder
// (as a job submitted again): followed, it ends where the resumed search ends, not at the
// interrupted run's account, which the resumed search removes as it begins.
TEST(Follow, AnInterruptedSearchResumedIsFollowedToItsRealEnd) {
    const std::string dir = fresh_dir("resumed");
    const std::string fird = FIRD_BINARY;
    const auto stopped =
        shell("sh -c '" + fird + " optimize " + kMirror + " --method grid --out " + dir +
              " >/dev/null 2>&1 & pid=$!; i=0; while [ $i -lt 600 ]; do n=$(cat " + dir +
              "/history.csv 2>/dev/null | wc -l); [ $n -gt 40 ] && break; sleep 0.05; "
              "i=$((i+1)); done; kill -TERM $pid; wait $pid; exit 0'");
    ASSERT_EQ(stopped.code, 0) << stopped.out;
    const auto once = run("follow " + dir + " --once --json");
    ASSERT_EQ(once.code, 0) << once.out;
    const auto j0 = nlohmann::json::parse(once.out.substr(once.out.find('{')));
    ASSERT_TRUE(j0.at("ended").get<bool>()) << j0; // the interrupted run's end, all its rows
    EXPECT_EQ(j0.at("stopped"), "interrupted");
    EXPECT_LT(j0.at("evaluations").get<int>(), 169);
    // The resumed search in the background; the follower once it has begun (its old end
    // removed, or, on a fast machine, already written again).
    const auto r = shell("(" + fird + " optimize " + kMirror + " --resume " + dir +
                         " >/dev/null 2>&1 &); i=0; while [ $i -lt 600 ] && [ -f " + dir +
                         "/search.json ] && grep -q interrupted " + dir +
                         "/search.json; do sleep 0.05; i=$((i+1)); done; timeout 300 " + fird +
                         " follow " + dir + " --interval 0.05 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    const auto search = read_json(dir + "/search.json");
    EXPECT_EQ(j.at("evaluations"), 169);
    EXPECT_EQ(j.at("stopped"), "exhausted");
    EXPECT_EQ(j.at("evaluations"), search.at("evaluations"));
    EXPECT_EQ(j.at("best_parameters"), search.at("best_parameters"));
}

// A scene's name goes into comment lines: a newline in it must not start a line of its own
// (a command in run.sh, a broken scene.toml); and a scene a search would refuse (no
// [target]) gets no job.
TEST(ClusterJob, ASceneNameStaysInItsCommentLineAndASceneWithoutATargetGetsNoJob) {
    std::string text = read_text(kMirror);
    const std::string name = "name = \"mirror search\"";
    ASSERT_NE(text.find(name), std::string::npos);
    text.replace(text.find(name), name.size(), "name = \"two\\ntouch INJECTED\"");
    const std::string scene = fresh_dir("newline") + ".toml", job = fresh_dir("newline_job");
    std::ofstream(scene) << text;
    const auto w = run("optimize " + scene + " --method grid --out " + job + " --job-script");
    ASSERT_EQ(w.code, 0) << w.out;
    // (scene.toml keeps the name whole, in a TOML multi-line string: it must read back.)
    for (const char* file : {"/run.sh", "/slurm.sh"}) {
        std::istringstream lines(read_text(job + file));
        for (std::string line; std::getline(lines, line);)
            EXPECT_NE(line.rfind("touch", 0), 0u) << file << ": " << line;
    }
    const auto t = run("trace " + job + "/scene.toml --rays 1000 --json");
    EXPECT_EQ(t.code, 0) << t.out;

    std::string untargeted = read_text(kMirror);
    untargeted.resize(untargeted.find("[target]"));
    const std::string bare = fresh_dir("untargeted") + ".toml", none = fresh_dir("untargeted_job");
    std::ofstream(bare) << untargeted;
    const auto refused = run("optimize " + bare + " --out " + none + " --job-script");
    EXPECT_EQ(refused.code, 1) << refused.out;
    EXPECT_NE(refused.out.find("[target] is missing"), std::string::npos) << refused.out;
    EXPECT_FALSE(std::filesystem::exists(none + "/run.sh"));
    // Nor does a follower write into the folder it follows.
    EXPECT_EQ(run("follow " + direct_search() + " --once --out " + direct_search()).code, 2);
}

} // namespace
