// The `fird` command's contract for bad input: one line, the usage, exit code 2.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/ray_files_fixture.hpp"
#include "io/scene_file.hpp"
#include "model/press_measures.hpp"
#include "run_fird.hpp"

namespace {

using fird::test::Result;

Result run_env(const std::string& env, const std::string& args) {
    return fird::test::run_fird(env, args);
}

Result run(const std::string& args) {
    return run_env("", args);
}

TEST(Cli, UnknownSubcommandIsUsageErrorWithCode2) {
    const auto r = run("frobnicate");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("usage"), std::string::npos) << r.out;
}

TEST(Cli, UnknownOptionIsUsageErrorWithCode2) {
    const auto r = run("info --no-such-option");
    EXPECT_EQ(r.code, 2) << r.out;
}

TEST(Cli, NoSubcommandIsUsageError) {
    EXPECT_EQ(run("").code, 2);
}

TEST(Cli, HelpExitsZero) {
    EXPECT_EQ(run("--help").code, 0);
}

TEST(Cli, InfoJsonHasTheLimitsThatMatter) {
    const auto r = run("info --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_FALSE(j["chosen"]["name"].get<std::string>().empty());
    for (const char* key :
         {"max_compute_workgroup_size", "max_compute_workgroup_count", "max_storage_buffer_range",
          "subgroup_size", "float32_atomic_add", "timestamps"})
        EXPECT_TRUE(j["limits"].contains(key)) << key;
    const std::string queue = j["work_queue"].get<std::string>();
    EXPECT_TRUE(queue == "own" || queue == "shared") << queue;
}

// The CPU's own flags, read from the kernel's /proc/cpuinfo.
std::vector<std::string> cpu_flags() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("flags", 0) != 0) continue;
        std::istringstream words(line.substr(line.find(':') + 1));
        return {std::istream_iterator<std::string>(words), {}};
    }
    return {};
}

bool has_flags(const std::vector<std::string>& flags, std::initializer_list<const char*> wanted) {
    return std::all_of(wanted.begin(), wanted.end(), [&](const char* f) {
        return std::find(flags.begin(), flags.end(), f) != flags.end();
    });
}

// FIRD asks lavapipe for the CPU's widest vectors in a process that only computes: 512
// bits where the CPU has AVX-512 (its f, bw, dq and vl subsets, which llvmpipe's 512-bit
// code uses), else Mesa 22.3's default, 256 bits with AVX (Mesa keeps 256 on AVX-512 too)
// and 128 without. A process that draws keeps Mesa's default (Mesa 22.3 crashes in LLVM
// compiling a fragment shader at 512). The user's LP_NATIVE_VECTOR_WIDTH wins. Wherever a
// width is set, the shader cache moves to a folder of that width's own, since lavapipe's
// cache keys a shader without it (docs/architecture.md, "CPU vector width").
TEST(Cli, LavapipeComputesAtTheCpusWidestVectorsUnlessItDrawsOrTheUserChose) {
    // llvmpipe names its width ("llvmpipe (LLVM 15.0.6, 256 bits)") and runs a subgroup
    // per vector of 32-bit lanes.
    const auto bits_and_lanes = [](const Result& r) {
        const auto j = nlohmann::json::parse(r.out);
        const std::string name = j["chosen"]["name"].get<std::string>();
        const std::size_t comma = name.rfind(", ");
        return std::pair{name.substr(comma + 2, name.find(' ', comma + 2) - comma - 2),
                         j["limits"]["subgroup_size"].get<int>()};
    };
    const std::vector<std::string> flags = cpu_flags();
#if defined(__x86_64__)
    const int mesa_bits = has_flags(flags, {"avx"}) ? 256 : 128;
    const int compute_bits =
        has_flags(flags, {"avx512f", "avx512bw", "avx512dq", "avx512vl"}) ? 512 : mesa_bits;
#endif
    const std::string cache = ::testing::TempDir() + "/fird_width_cache";
    std::filesystem::remove_all(cache);
    const std::string env = "env -u LP_NATIVE_VECTOR_WIDTH MESA_SHADER_CACHE_DIR=" + cache;
    const auto unset = run_env(env, "--device llvmpipe info --json");
    ASSERT_EQ(unset.code, 0) << unset.out;
#if defined(__x86_64__)
    EXPECT_EQ(bits_and_lanes(unset), std::pair(std::to_string(compute_bits), compute_bits / 32))
        << unset.out;
    EXPECT_EQ(std::filesystem::exists(cache + "/lavapipe-512bit/mesa_shader_cache"),
              compute_bits == 512);
#endif
    const auto chosen = run_env("MESA_SHADER_CACHE_DIR=" + cache + " LP_NATIVE_VECTOR_WIDTH=128",
                                "--device llvmpipe info --json");
    ASSERT_EQ(chosen.code, 0) << chosen.out;
    EXPECT_EQ(bits_and_lanes(chosen), std::pair(std::string("128"), 4)) << chosen.out;
    EXPECT_TRUE(std::filesystem::exists(cache + "/lavapipe-128bit/mesa_shader_cache"));
#if FIRD_HAS_UI && defined(__x86_64__)
    // The workbench offscreen draws: Mesa's width, Mesa's cache folder.
    std::filesystem::remove_all(cache);
    const auto drawn =
        run_env(env + " XDG_CONFIG_HOME=" + ::testing::TempDir() + "/fird_width_config timeout 120",
                "--device llvmpipe gui --offscreen 200x200 --frames 2 --stats");
    ASSERT_EQ(drawn.code, 0) << drawn.out;
    const std::string device =
        nlohmann::json::parse(drawn.out.substr(drawn.out.find('{')))["device"];
    EXPECT_NE(device.find(", " + std::to_string(mesa_bits) + " bits"), std::string::npos) << device;
    EXPECT_TRUE(std::filesystem::exists(cache + "/mesa_shader_cache"));
    EXPECT_FALSE(std::filesystem::exists(cache + "/lavapipe-512bit"));
#endif
}

// The fast path's results may not depend on the subgroup size (a real GPU's is 32 or 64,
// lavapipe's the lanes of its vectors: 4, 8 or 16 here): the tally's packed counters, the
// appends' ballots, the order pass and the walk's rounds all work per subgroup. Model C at
// 2e5 rays reflects up to five times, and its first bounces are ordered (more than
// kOrderMinRays rays each). The far field is integer counts, so it must agree byte for
// byte; so must every count of rays. (The l2 is a float reduction whose order follows
// the subgroup size: not compared here, tests/reduction_bound.hpp bounds it.)
TEST(Cli, TheFastPathGivesTheSameFarFieldAtEverySubgroupSize) {
    const auto read_bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    std::map<int, std::pair<nlohmann::json, std::string>> by_lanes;
    for (const int bits : {128, 256, 512}) {
        const std::string dir = ::testing::TempDir() + "/fird_lanes_" + std::to_string(bits);
        // Without the on-disk shader cache: it keys a shader without the width, so a pass
        // compiled at one width could be found and run at another (docs/architecture.md,
        // "CPU vector width").
        const auto r =
            run_env("MESA_SHADER_CACHE_DISABLE=true LP_NATIVE_VECTOR_WIDTH=" + std::to_string(bits),
                    "--device llvmpipe trace " + std::string(FIRD_SOURCE_DIR) +
                        "/scenes/model_c.toml --rays 2e5 --json --out " + dir);
        ASSERT_EQ(r.code, 0) << r.out;
        const auto j = nlohmann::json::parse(r.out);
        ASSERT_NE(j["device"].get<std::string>().find(std::to_string(bits) + " bits"),
                  std::string::npos)
            << j["device"];
        by_lanes[bits / 32] = {j, read_bytes(dir + "/farfield.npy")};
    }
    const auto& [first_json, first_farfield] = by_lanes.begin()->second;
    ASSERT_GT(first_farfield.size(), 1000u);
    EXPECT_GT(first_json["rays_reflected"].get<int>(), 0);
    for (const auto& [lanes, result] : by_lanes) {
        EXPECT_TRUE(result.second == first_farfield) << lanes << " lanes";
        for (const char* key : {"rays_effective", "rays_discarded", "rays_direct", "rays_reflected",
                                "rays_aborted", "rays_lost"})
            EXPECT_EQ(result.first[key], first_json[key]) << key << " at " << lanes << " lanes";
    }
}

TEST(Cli, UnknownDeviceNameExitsOneWithOneLine) {
    const auto r = run("--device no-such-gpu info");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no-such-gpu"), std::string::npos) << r.out;
}

TEST(Cli, NoVulkanDriverAtAllExitsOneWithOneLine) {
    // Point the loader at an empty driver list: no device at all.
    const auto r =
        run_env("VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json", "info");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("no Vulkan"), std::string::npos) << r.out;
}

TEST(Cli, BadSceneIsOneLineNamingFileKeyAndLineWithExitCode1) {
    const std::string path = ::testing::TempDir() + "/bad_scene.toml";
    FILE* f = std::fopen(path.c_str(), "w");
    ASSERT_TRUE(f);
    std::fputs("[source]\ntype = \"sphere\"\ncenter_mm = [0.0, 0.0, 0.0]\nradius_mm = "
               "-1.0\nflux_lm = 5.0\n",
               f);
    std::fclose(f);
    const auto r = run("trace " + path + " --backend cpu");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(path + ":4: [source] radius_mm: must be > 0"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    std::remove(path.c_str());
}

TEST(Cli, TraceJsonHasEveryContractField) {
    const auto r = run("trace " + std::string(FIRD_SOURCE_DIR) +
                       "/scenes/model_a.toml --backend cpu --rays 20000 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"rays_emitted", "rays_effective", "rays_reflected", "energy_emitted_lm",
                            "energy_farfield_lm", "energy_direct_lm", "energy_discarded_lm",
                            "energy_lost_lm", "energy_absorbed_lm", "l2", "timings_ms", "device"})
        EXPECT_TRUE(j.contains(key)) << key;
    for (const char* key : {"rayset", "heightfield", "trace", "histogram", "compare", "total"})
        EXPECT_TRUE(j["timings_ms"].contains(key)) << key;
    EXPECT_EQ(j["rays_emitted"].get<std::uint64_t>(), 20000u);
    const double sum = j["energy_discarded_lm"].get<double>() +
                       j["energy_direct_lm"].get<double>() + j["energy_farfield_lm"].get<double>() +
                       j["energy_lost_lm"].get<double>();
    EXPECT_NEAR(sum, j["energy_emitted_lm"].get<double>(), 1e-9);
}

// A finished reflector (R = 0.9, a 1 degree lobe) with the direct light binned: the five
// energy terms add up to the emitted flux (DESIGN.md §2), the absorbed one is the share
// the reflections took (between 1 - R and 1 - R^5 of the reflected rays' flux), and the
// far field holds the reflected and the direct light, on both backends.
TEST(Cli, AFinishedReflectorAccountsForTheAbsorbedFlux) {
    for (const char* backend : {"gpu", "cpu"}) {
        SCOPED_TRACE(backend);
        const auto r =
            run("trace " + std::string(FIRD_SOURCE_DIR) +
                "/scenes/model_b_aluminium.toml --rays 50000 --json --backend " + backend);
        ASSERT_EQ(r.code, 0) << r.out;
        const auto j = nlohmann::json::parse(r.out);
        const auto lm = [&](const char* key) { return j.at(key).get<double>(); };
        EXPECT_NEAR(lm("energy_discarded_lm") + lm("energy_direct_lm") + lm("energy_farfield_lm") +
                        lm("energy_lost_lm") + lm("energy_absorbed_lm"),
                    lm("energy_emitted_lm"), 1e-9 * lm("energy_emitted_lm"));
        const double reflected_rays_lm = lm("energy_farfield_lm") + lm("energy_absorbed_lm");
        EXPECT_GE(lm("energy_absorbed_lm"), 0.1 * reflected_rays_lm);
        EXPECT_LE(lm("energy_absorbed_lm"), (1.0 - std::pow(0.9, 5)) * reflected_rays_lm);
        EXPECT_NEAR(lm("energy_binned_lm"), lm("energy_farfield_lm") + lm("energy_direct_lm"),
                    1e-9 * lm("energy_emitted_lm"));
        EXPECT_GT(lm("energy_direct_lm"), 0.0);
    }
}

// Batches only cut the work into submissions: the rays are indexed, not drawn per batch
// (a finish's draws too: keyed on the ray's index and bounce), so the tally and the l2 are
// the same with any --max-batch-rays.
TEST(Cli, SmallerBatchesTraceTheSameRays) {
    for (const char* name : {"model_b.toml", "model_b_aluminium.toml"}) {
        SCOPED_TRACE(name);
        const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/" + name;
        const auto whole = run("trace " + scene + " --rays 100000 --json");
        const auto cut = run("--max-batch-rays 9000 trace " + scene + " --rays 100000 --json");
        ASSERT_EQ(whole.code, 0) << whole.out;
        ASSERT_EQ(cut.code, 0) << cut.out;
        const auto a = nlohmann::json::parse(whole.out), b = nlohmann::json::parse(cut.out);
        for (const char* key :
             {"rays_effective", "rays_reflected", "rays_by_reflections", "rays_lost"})
            EXPECT_EQ(a[key], b[key]) << key;
        EXPECT_NEAR(a["l2"].get<double>(), b["l2"].get<double>(), 1e-9 * a["l2"].get<double>());
        EXPECT_NEAR(a["energy_absorbed_lm"].get<double>(), b["energy_absorbed_lm"].get<double>(),
                    1e-9);
    }
}

// fird trace --profile: one row per bounce, read by key; the rays of bounce 0 are the
// effective rays; the cpu backend has no trace passes to profile (a usage error).
TEST(Cli, TraceProfileHasARowPerBounce) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/model_b.toml";
    // --rays takes the 1e6 style as every other command's --rays does.
    const auto r = run("trace " + scene + " --rays 2e4 --json --profile");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["rays_emitted"].get<std::uint64_t>(), 20000u);
    ASSERT_TRUE(j.contains("profile"));
    const auto& rows = j["profile"];
    ASSERT_FALSE(rows.empty());
    EXPECT_EQ(rows[0]["rays"].get<std::uint64_t>(), j["rays_effective"].get<std::uint64_t>());
    for (const auto& row : rows) {
        for (const char* key :
             {"bounce", "rays", "trace_ms", "order_ms", "ns_per_ray", "steps_per_ray",
              "leaf_tests_per_ray", "lane_utilization", "leaf_lane_utilization"})
            EXPECT_TRUE(row.contains(key)) << key;
        EXPECT_GT(row["steps_per_ray"].get<double>(), 0.0);
        for (const char* key : {"lane_utilization", "leaf_lane_utilization"}) {
            EXPECT_GT(row[key].get<double>(), 0.0) << key;
            EXPECT_LE(row[key].get<double>(), 1.0) << key;
        }
    }
    EXPECT_FALSE(nlohmann::json::parse(run("trace " + scene + " --rays 2000 --json").out)
                     .contains("profile"));
    const auto cpu = run("trace " + scene + " --rays 2000 --backend cpu --profile");
    EXPECT_EQ(cpu.code, 2) << cpu.out;
}

// The luminaire files hold what the far field holds, in absolute candela for the source's
// real flux: the finished Model B with its direct light (1100 lm source). The IES file is
// LM-63-2019 with its required keywords and a simulation's file generation type (read here
// as text, line by line); the EULUMDAT file's lamp is the source and its light output
// ratio the far field's share of it (read as text: line 23 LORL, the first lamp set's
// flux at line 29 of the fixed header).
TEST(Cli, TraceOutWritesNpyPicturesAndLuminaireFiles) {
    const std::string dir = ::testing::TempDir() + "/fird_out";
    const auto r =
        run("trace " + std::string(FIRD_SOURCE_DIR) +
            "/scenes/model_b_aluminium.toml --backend cpu --rays 20000 --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* name :
         {"farfield.npy", "farfield.png", "target.npy", "target.png", "difference.png",
          "farfield.ies", "farfield.ldt", "polar.png", "isocandela.png", "illuminance.png"}) {
        FILE* f = std::fopen((dir + "/" + name).c_str(), "rb");
        EXPECT_TRUE(f) << name;
        if (f) std::fclose(f);
    }
    const double binned_lm = nlohmann::json::parse(r.out)["energy_binned_lm"].get<double>();
    for (const char* name : {"farfield.ies", "farfield.ldt"}) {
        const auto info = run("photometry info --json " + dir + "/" + name);
        ASSERT_EQ(info.code, 0) << info.out;
        EXPECT_NEAR(nlohmann::json::parse(info.out)["flux_integrated_lm"].get<double>(), binned_lm,
                    1e-3 * binned_lm)
            << name;
    }
    const auto lines = [](const std::string& path) {
        std::ifstream in(path);
        std::vector<std::string> out;
        for (std::string l; std::getline(in, l);)
            out.push_back(l.substr(0, l.find('\r')));
        return out;
    };
    const std::vector<std::string> ies = lines(dir + "/farfield.ies");
    ASSERT_GT(ies.size(), 12u);
    EXPECT_EQ(ies[0], "IES:LM-63-2019");
    for (const char* keyword : {"[TEST] ", "[TESTLAB] ", "[ISSUEDATE] ", "[MANUFAC] "})
        EXPECT_TRUE(std::any_of(ies.begin(), ies.end(), [&](const std::string& l) {
            return l.rfind(keyword, 0) == 0;
        })) << keyword;
    const auto tilt = std::find(ies.begin(), ies.end(), "TILT=NONE");
    ASSERT_NE(tilt, ies.end());
    EXPECT_EQ((tilt + 1)->substr(0, 5), "1 -1 ") << "absolute photometry";
    EXPECT_EQ(*(tilt + 2), "1 1.00010 0") << "a simulation's file generation type";
    const std::vector<std::string> ldt = lines(dir + "/farfield.ldt");
    ASSERT_GT(ldt.size(), 30u);
    EXPECT_NEAR(std::stod(ldt[28]), 1100.0, 1e-9) << "the lamp is the source";
    EXPECT_NEAR(std::stod(ldt[22]), 100.0 * binned_lm / 1100.0, 0.1) << "LORL %";
    const auto ldt_info =
        nlohmann::json::parse(run("photometry info --json " + dir + "/farfield.ldt").out);
    EXPECT_NEAR(ldt_info["flux_declared_lm"].get<double>(), binned_lm, 1e-3 * binned_lm);
}

// A CSV file read by column name (header first; fields may be quoted, none holds a comma).
struct Csv {
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
    std::string at(std::size_t row, const std::string& column) const {
        const auto c = std::find(header.begin(), header.end(), column);
        EXPECT_NE(c, header.end()) << column;
        if (c == header.end() || row >= rows.size()) return {};
        const auto k = std::size_t(c - header.begin());
        return k < rows[row].size() ? rows[row][k] : std::string{};
    }
    double number(std::size_t row, const std::string& column) const {
        const std::string v = at(row, column);
        return v.empty() ? std::nan("") : std::stod(v);
    }
};

Csv read_csv(const std::string& path) {
    Csv csv;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        std::vector<std::string> cells;
        std::istringstream is(line);
        for (std::string c; std::getline(is, c, ',');) {
            if (c.size() >= 2 && c.front() == '"' && c.back() == '"') c = c.substr(1, c.size() - 2);
            cells.push_back(c);
        }
        if (line.back() == ',') cells.emplace_back();
        if (csv.header.empty())
            csv.header = cells;
        else
            csv.rows.push_back(cells);
    }
    return csv;
}

// Runs `fird bench` on the flat mirror with `options` into a fresh directory under
// `name`; returns that directory and bench.csv.
std::pair<std::string, Csv> bench_flat_mirror(const std::string& name, const std::string& options) {
    const std::string dir = ::testing::TempDir() + "/" + name;
    const auto r = run("bench " + std::string(FIRD_SOURCE_DIR) + "/scenes/test/flat_mirror.toml " +
                       options + " --out " + dir + " 2>/dev/null");
    EXPECT_EQ(r.code, 0) << r.out;
    return {dir, read_csv(dir + "/bench.csv")};
}

TEST(Cli, BenchWritesTableCsvAndPlot) {
    const auto [dir, csv] = bench_flat_mirror(
        "fird_bench", "--heightfields 40x40,61x37 --rays 2e4 --reference-rays 1e5");
    ASSERT_EQ(csv.rows.size(), 4u); // 2 height fields x 1 ray count x 2 hit modes
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
        ASSERT_EQ(csv.rows[i].size(), csv.header.size());
        // l2 and noise are positive and finite; no aborted rays; no same-rays reference.
        EXPECT_GT(csv.number(i, "trace_ms"), 0.0);
        EXPECT_GT(csv.number(i, "l2_lm"), 0.0);
        EXPECT_GT(csv.number(i, "noise_lm"), 0.0);
        EXPECT_EQ(csv.at(i, "l2_same_rays_lm"), "");
        EXPECT_EQ(csv.at(i, "aborted"), "0");
        // The scene's stratified sampler: its noise measured, not the multinomial formula's.
        EXPECT_EQ(csv.at(i, "noise_from"), "replicate");
    }
    FILE* png = std::fopen((dir + "/bench.png").c_str(), "rb");
    EXPECT_TRUE(png);
    if (png) std::fclose(png);
}

// With --same-rays each row is also compared with the reference traced from its own
// rays: on a flat mirror (both hit modes exact there) that l2 holds only rays float
// rounding sends into another bin. Each such ray takes its energy E from one cell to
// another, so k of them give l2 = E sqrt(2 k): fewer than 1 in 400 may move (today ~1 in
// 1000 in the paper mode, 1 in 10^4 refined; an inaccurate asin in the device's binning
// once moved 1 in 133).
TEST(Cli, BenchSameRaysErrorIsTheDiscretizationAlone) {
    const auto [dir, csv] = bench_flat_mirror(
        "fird_bench_same", "--heightfields 64x64 --rays 2e4 --reference-rays 1e5 --same-rays");
    ASSERT_EQ(csv.rows.size(), 2u); // 2 hit modes
    for (std::size_t i = 0; i < csv.rows.size(); ++i) {
        const double l2 = csv.number(i, "l2_lm"), noise = csv.number(i, "noise_lm");
        const double same = csv.number(i, "l2_same_rays_lm");
        // The noise is the sampler's own (measured from a replicate trace): the plain l2 is
        // that noise, within the scatter of one run and one replicate pair over the
        // 360 x 180 cells (~2 % each) five times over.
        EXPECT_NEAR(l2 / noise, 1.0, 0.1);
        EXPECT_GE(same, 0.0);
        const double energy_per_ray_lm = 100.0 / 2e4; // the scene's 100 lm over 2e4 rays
        const double moved = 0.5 * (same / energy_per_ray_lm) * (same / energy_per_ray_lm);
        EXPECT_LT(moved, csv.number(i, "effective") / 400.0);
    }
}

// fird bench --candidates: one row per scene with the candidate's wall time and its stages
// (the compare runs: the scene has a target), read by name; one ray count only.
TEST(Cli, BenchCandidatesTimesASearchsCandidate) {
    const std::string dir = ::testing::TempDir() + "/fird_bench_candidates";
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/model_b.toml";
    const auto r = run("bench --candidates " + scene + " --rays 2e4 --reps 3 --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const Csv csv = read_csv(dir + "/candidates.csv");
    ASSERT_EQ(csv.rows.size(), 1u);
    EXPECT_EQ(csv.at(0, "rays"), "20000");
    EXPECT_EQ(csv.at(0, "reps"), "3");
    const double stages = csv.number(0, "heightfield_ms") + csv.number(0, "trace_ms") +
                          csv.number(0, "histogram_ms") + csv.number(0, "compare_ms");
    EXPECT_GT(csv.number(0, "trace_ms"), 0.0);
    EXPECT_GT(csv.number(0, "heightfield_ms"), 0.0); // rebuilt for every candidate
    EXPECT_GT(csv.number(0, "compare_ms"), 0.0);
    EXPECT_GE(csv.number(0, "candidate_ms"), 0.5 * stages);
    // Beside it, 16 candidates a batch (the default --batch): 2e4 rays each would fit one
    // submission, but each candidate's height field and far field (about 35 MB at the
    // scene's grids) must fit a quarter of the device-local heap beside the rest (lavapipe
    // reports 2 GiB: about 8 of them), so the batch is waited on a few times, fewer than
    // once per candidate.
    EXPECT_EQ(csv.at(0, "batch"), "16");
    EXPECT_GT(csv.number(0, "batch_candidate_ms"), 0.0);
    EXPECT_GE(csv.number(0, "batch_submissions"), 1.0);
    EXPECT_LE(csv.number(0, "batch_submissions"), 4.0);
    const auto two = run("bench --candidates " + scene + " --rays 1e4,2e4 --out " + dir);
    EXPECT_EQ(two.code, 2) << two.out;
}

// A malformed option value is a usage error (exit 2) naming the option.
TEST(Cli, BenchRejectsMalformedListsAsUsageErrors) {
    for (const char* bad : {"--heightfields 300by200", "--rays lots", "--modes fast"}) {
        const auto r = run(std::string("bench ") + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find(std::string(bad).substr(0, std::string(bad).find(' '))),
                  std::string::npos)
            << r.out;
    }
}

TEST(Cli, PhotometryInfoJsonHasEveryContractField) {
    const std::string file =
        std::string(FIRD_SOURCE_DIR) + "/tests/photometry/data/corpus/luxpy_pair_quadrant.ldt";
    const auto r = run("photometry info --json " + file);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"format", "version", "photometric_type", "symmetry", "n_vertical",
                            "n_horizontal", "flux_declared_lm", "flux_integrated_lm", "peak_cd"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["format"], "ldt");
    EXPECT_EQ(j["symmetry"], "quadrant");
    EXPECT_NEAR(j["flux_integrated_lm"].get<double>(), 5280.7, 0.1);
}

TEST(Cli, PhotometryConvertWritesEveryFormatAndRefusesBadInputInOneLine) {
    const std::string src =
        std::string(FIRD_SOURCE_DIR) + "/tests/photometry/data/corpus/cu_3_indoor_asym360.ies";
    const std::string dir = ::testing::TempDir();
    for (const char* out : {"c.ldt", "c.ies", "c.npy", "c.png"}) {
        const auto r = run("photometry convert " + src + " " + dir + out);
        EXPECT_EQ(r.code, 0) << out << ": " << r.out;
    }
    // The LDT written back holds the same flux.
    const auto j = nlohmann::json::parse(run("photometry info --json " + dir + "c.ldt").out);
    EXPECT_NEAR(j["flux_integrated_lm"].get<double>(), 13359.57, 13.4);
    const auto bad = run("photometry info " + dir + "c.npy");
    EXPECT_EQ(bad.code, 1) << bad.out;
    EXPECT_EQ(std::count(bad.out.begin(), bad.out.end(), '\n'), 1) << bad.out;
    const auto missing = run("photometry info /nonexistent/x.ies");
    EXPECT_EQ(missing.code, 1);
    EXPECT_NE(missing.out.find("/nonexistent/x.ies: cannot open"), std::string::npos)
        << missing.out;
}

TEST(Cli, TraceAgainstAnIesTargetGivesL2OnBothBackends) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/model_a_ies.toml";
    const auto gpu = run("trace " + scene + " --rays 200000 --json");
    ASSERT_EQ(gpu.code, 0) << gpu.out;
    const auto cpu = run("trace " + scene + " --rays 200000 --backend cpu --json");
    ASSERT_EQ(cpu.code, 0) << cpu.out;
    const double l2_gpu = nlohmann::json::parse(gpu.out)["l2"].get<double>();
    const double l2_cpu = nlohmann::json::parse(cpu.out)["l2"].get<double>();
    // Same scene and rays: the two tracers' distances to the same target agree closely.
    EXPECT_NEAR(l2_gpu, l2_cpu, 0.05 * l2_cpu);
}

TEST(Cli, MissingOrBrokenIesTargetIsOneLineNamingSceneKeyAndFile) {
    std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/model_a_ies.toml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = "targets/model_a_target.ies";
    text.replace(text.find(from), from.size(), "broken.ies");
    const std::string scene = ::testing::TempDir() + "/ies_target_scene.toml";
    std::ofstream(scene) << text;
    std::remove((::testing::TempDir() + "/broken.ies").c_str());
    auto r = run("trace " + scene + " --rays 1000");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(scene + ": [target] file: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("broken.ies: cannot open"), std::string::npos) << r.out;
    std::ofstream(::testing::TempDir() + "/broken.ies")
        << "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3";
    r = run("trace " + scene + " --rays 1000 --backend cpu");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("broken.ies:3: "), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// fird tolerance: the JSON's keys (DESIGN.md's contract for the command), the CSV's rows
// (the nominal one, then K per run: joint and each tolerance's) read by column name, and
// the picture.
TEST(Cli, ToleranceWritesItsSpreadsSensitivitiesAndRows) {
    const std::string dir = ::testing::TempDir() + "/fird_tolerance";
    const auto r = run("tolerance " + std::string(FIRD_SOURCE_DIR) +
                       "/scenes/test/focused_paraboloid_search.toml --rays 5000 "
                       "--realisations 3 --source-shift-mm 0.2 --reflectance-sd 0.02 --json "
                       "--out " +
                       dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["realisations"].get<int>(), 3);
    for (const char* metric : {"l2", "efficiency", "peak_cd"})
        for (const char* key : {"median", "p5", "p95"})
            EXPECT_TRUE(j[metric].contains(key)) << metric << " " << key;
    ASSERT_EQ(j["sensitivities"].size(), 2u);
    EXPECT_EQ(j["sensitivities"][0]["tolerance"], "source_shift");
    EXPECT_EQ(j["sensitivities"][1]["tolerance"], "reflectance");
    const Csv csv = read_csv(dir + "/tolerance.csv");
    ASSERT_EQ(csv.rows.size(), 1u + 3u * 3u);
    EXPECT_EQ(csv.at(0, "kind"), "nominal");
    EXPECT_EQ(csv.at(1, "kind"), "joint");
    EXPECT_EQ(csv.number(0, "source_dx_mm"), 0.0);
    EXPECT_GT(csv.number(1, "efficiency"), 0.0);
    FILE* png = std::fopen((dir + "/tolerance.png").c_str(), "rb");
    EXPECT_TRUE(png);
    if (png) std::fclose(png);
}

} // namespace

// fird optimize: the JSON contract, the files of --out, and one history row per
// evaluation.
TEST(CliOptimize, JsonHasTheContractKeysAndOutHasTheFiles) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_out";
    std::filesystem::remove_all(dir);
    const auto r = run("optimize " + std::string(FIRD_SOURCE_DIR) +
                       "/scenes/test/mirror_search.toml --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    for (const char* key :
         {"method", "evaluations", "infeasible", "best_parameters", "best_l2", "final_l2",
          "noise_floor_l2", "rays_per_evaluation", "time_s", "stopped"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["method"], "auto");
    EXPECT_EQ(j["backend"], "gpu");
    EXPECT_TRUE(j["best_parameters"].contains("sx") && j["best_parameters"].contains("sy"));
    for (const char* name :
         {"history.csv", "progress.png", "best.toml", "search.json", "options.json", "farfield.png",
          "target.png", "difference.png", "farfield.npy", "reflector.step", "reflector.stl",
          "manufacturability.json", "manufacturability.png", "polar.png", "isocandela.png",
          "illuminance.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + name)) << name;
    EXPECT_TRUE(j["constraints"].is_array()); // none in this scene
    // The report is the best reflector's: a plane, its slope atan(hypot(sx, sy)).
    std::ifstream press(dir + "/manufacturability.json");
    const auto m = nlohmann::json::parse(press);
    const double sx = j["best_parameters"]["sx"], sy = j["best_parameters"]["sy"];
    EXPECT_NEAR(m["max_slope_deg"].get<double>(),
                std::atan(std::hypot(sx, sy)) * 180.0 / std::numbers::pi, 1e-9);
    std::ifstream history(dir + "/history.csv");
    std::string line;
    std::getline(history, line);
    EXPECT_EQ(line.rfind("index,stage,stage_name,rays,", 0), 0u) << line;
    std::size_t rows = 0;
    while (std::getline(history, line))
        ++rows;
    EXPECT_EQ(rows, j["evaluations"].get<std::size_t>());
    // best.toml traces as it is, from anywhere, and gives the best reflector.
    const auto t = run("trace " + dir + "/best.toml --json --rays 1000");
    EXPECT_EQ(t.code, 0) << t.out;
}

// A press's limit nothing in the box meets (the focused paraboloid rises from z0 = -10 to
// the clamp at 0 for every fx, fy: 10 mm deep): one line naming the key, exit 1, before
// the device is opened (there is none).
TEST(CliOptimize, AConstraintNoCandidateMeetsIsRefusedNamingTheKey) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_unmeetable";
    std::filesystem::create_directories(dir);
    const std::string scene = dir + "/steep.toml";
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) +
                         "/scenes/test/focused_paraboloid_search.toml");
        std::ofstream out(scene);
        out << in.rdbuf() << "\n[reflector.constraints]\nmax_depth_mm = 5.0\n";
    }
    const auto r = run_env("VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json",
                           "optimize " + scene);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("[reflector.constraints] max_depth_mm = 5:"), std::string::npos) << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// A start outside its bounds (fx = 5 below [10, 20]) would be clamped silently into the
// box: refused instead, one line naming the table and the parameter, before the device.
TEST(CliOptimize, AStartOutsideItsBoundsIsRefusedNamingTheParameter) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_start_outside";
    std::filesystem::create_directories(dir);
    const std::string scene = dir + "/outside.toml";
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/model_a.toml");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto at = text.find("fx = 13.0");
        ASSERT_NE(at, std::string::npos);
        text.replace(at, 9, "fx = 5.0");
        std::ofstream(scene) << text;
    }
    const auto r = run_env("VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json",
                           "optimize " + scene);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("[reflector.optimize] fx: the start 5 lies outside its bounds [10, 20]"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

// The profile family searched under the candela metric, end to end: its heights are the
// parameters h_<k>, history.csv's value column says the metric and its unit, the JSON
// names the metric and reports the photometrics of the best and of the target (each
// efficiency the far field's share of the source's 100 lm), and best.toml holds the
// heights found.
TEST(CliOptimize, AProfileSearchUnderTheCandelaMetricReportsItsPhotometrics) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_profile";
    std::filesystem::remove_all(dir);
    const std::string scene = dir + "_scene.toml";
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/test/profile_dish.toml");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text.replace(text.find("heights_mm = { min"),
                     std::string("heights_mm = { min = 0.0, max = 6.0, step = 0.05 }").size(),
                     "h_2 = { min = 0.4, max = 1.2, step = 0.1 }");
        text += "\n[target]\nseed = 2\nparameters = { h_2 = 1.0 }\n";
        std::ofstream(scene) << text;
    }
    const auto r = run("optimize " + scene + " --method grid --rays 2e4 --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    EXPECT_EQ(j["metric"], "candela_l2");
    EXPECT_EQ(j["metric_unit"], "cd");
    EXPECT_EQ(j["evaluations"].get<int>(), 9);
    EXPECT_TRUE(j["best_parameters"].contains("h_2"));
    for (const char* key : {"photometrics", "desired_photometrics"}) {
        const auto& p = j[key];
        EXPECT_GT(p["efficiency"].get<double>(), 0.2) << key;
        EXPECT_LE(p["efficiency"].get<double>(), 1.0) << key;
        EXPECT_GT(p["peak_cd"].get<double>(), 0.0) << key;
        EXPECT_GT(p["beam_angle_deg"]["C0"].get<double>(), 0.0) << key;
        EXPECT_GE(p["field_angle_deg"]["C90"].get<double>(),
                  p["beam_angle_deg"]["C90"].get<double>())
            << key;
    }
    std::ifstream history(dir + "/history.csv");
    std::string header;
    std::getline(history, header);
    EXPECT_NE(header.find(",h_2,candela_l2_cd,feasible,"), std::string::npos) << header;
    const fird::Scene best = fird::load_scene(dir + "/best.toml");
    EXPECT_EQ(best.reflector.family, fird::Family::Profile);
    EXPECT_EQ(best.reflector.parameters.at("h_2"), j["best_parameters"]["h_2"].get<double>());
}

// [optimize] smoothness: the search minimises l2 + weight x bending energy. Its history
// keeps each candidate's energy; the best is the lowest score of the search's stage
// (recomputed here from the history's columns); the JSON states the weight, the energies
// and the penalty; the best's energy is that of best.toml's reflector (measured here).
TEST(CliOptimize, ASmoothnessWeightedSearchMinimisesItsScoreAndReportsIt) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_smoothness";
    std::filesystem::remove_all(dir);
    const std::string scene = dir + "_scene.toml";
    // Heavy enough that the smoothest shape wins over the best fit: the lowest score and
    // the lowest l2 fall on different candidates, so ranking by l2 would be caught.
    constexpr double weight = 1000.0;
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/test/profile_dish.toml");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text.replace(text.find("heights_mm = { min"),
                     std::string("heights_mm = { min = 0.0, max = 6.0, step = 0.05 }").size(),
                     "h_2 = { min = 0.4, max = 1.2, step = 0.1 }");
        text.replace(text.find("metric = "), 0, "smoothness = 1000.0\n");
        text += "\n[target]\nseed = 2\nparameters = { h_2 = 1.0 }\n";
        std::ofstream(scene) << text;
    }
    const auto r = run("optimize " + scene + " --method grid --rays 2e4 --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    std::ifstream history(dir + "/history.csv");
    std::string line;
    std::getline(history, line);
    ASSERT_NE(line.find(",h_2,candela_l2_cd,smoothness,feasible,ms"), std::string::npos) << line;
    double lowest = HUGE_VAL, lowest_energy = 0.0, lowest_l2 = HUGE_VAL;
    int lowest_at = -1, lowest_l2_at = -1, rows = 0;
    while (std::getline(history, line)) {
        std::vector<std::string> cells;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ',');)
            cells.push_back(cell);
        ASSERT_EQ(cells.size(), 11u) << line;
        ++rows;
        if (cells[9] != "1") continue;
        const double score = std::stod(cells[7]) + weight * std::stod(cells[8]);
        EXPECT_GT(std::stod(cells[8]), 0.0) << "a dish bends: " << line;
        if (score < lowest)
            lowest = score, lowest_at = std::stoi(cells[0]), lowest_energy = std::stod(cells[8]);
        if (std::stod(cells[7]) < lowest_l2)
            lowest_l2 = std::stod(cells[7]), lowest_l2_at = std::stoi(cells[0]);
    }
    EXPECT_EQ(rows, 9);
    ASSERT_GE(lowest_at, 0);
    EXPECT_NE(lowest_at, lowest_l2_at) << "the weight should move the best off the best fit";
    EXPECT_EQ(j["best_evaluation"].get<int>(), lowest_at);
    EXPECT_NEAR(j["best_score"].get<double>(), lowest, 1e-12 * lowest);
    const auto& sm = j["smoothness"];
    EXPECT_EQ(sm["weight"].get<double>(), weight);
    EXPECT_EQ(sm["best_bending_energy"].get<double>(), lowest_energy);
    EXPECT_NEAR(sm["best_penalty"].get<double>(), weight * lowest_energy, 1e-12 * lowest);
    EXPECT_GT(sm["start_bending_energy"].get<double>(), 0.0);
    EXPECT_NEAR(sm["final_score"].get<double>(),
                j["final_l2"].get<double>() + weight * lowest_energy, 1e-9 * lowest);
    // The energy the search penalised is the best reflector's, as the press measures it.
    const fird::Scene best = fird::load_scene(dir + "/best.toml");
    EXPECT_NEAR(fird::search_bending_energy(fird::Surface::make(best.reflector, best.holder)),
                lowest_energy, 1e-12 * lowest_energy);
    std::ifstream report(dir + "/manufacturability.json");
    ASSERT_TRUE(report) << "the best part's report";
    EXPECT_GT(nlohmann::json::parse(report)["bending_energy"].get<double>(), 0.0);
}

// --start tailored (issue 26 item 5): refused where there is no profile to tailor (exit 2,
// the line naming --start); on a profile scene the search's first candidate is the tailored
// profile (CMA-ES traces its start first, as it is; NLopt's BOBYQA moves a start nearer a
// bound than its first step), the JSON says so with the start's metric, options.json records
// it, profiles.png draws it, and --resume continues from the same start.
TEST(CliOptimize, StartTailoredBeginsAtTheTailoredProfileAndResumesThere) {
    const std::string mirror = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    const auto refused = run("optimize " + mirror + " --start tailored");
    EXPECT_EQ(refused.code, 2) << refused.out;
    EXPECT_NE(refused.out.find("error: --start tailored: a tailored start is a profile's"),
              std::string::npos)
        << refused.out;
    EXPECT_EQ(run("optimize " + mirror + " --start nope").code, 2);

    const std::string dir = ::testing::TempDir() + "/fird_optimize_tailored";
    std::filesystem::remove_all(dir);
    const std::string scene = dir + "_scene.toml";
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/test/profile_dish.toml");
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text += "\n[target]\nseed = 2\nparameters = { h_3 = 1.4, h_4 = 2.6 }\n";
        std::ofstream(scene) << text;
    }
    const auto r =
        run("optimize " + scene +
            " --start tailored --method cmaes --max-evals 4 --rays 2e4 --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    const auto& start = j["start"];
    EXPECT_EQ(start["kind"], "tailored");
    EXPECT_TRUE(start["edge_ray"] == "crossing" || start["edge_ray"] == "diverging") << start;
    EXPECT_GT(start["metric_at_start"].get<double>(), 0.0);
    EXPECT_EQ(start["metric_at_start"], j["start_l2"]);
    ASSERT_EQ(start["parameters"].size(), 6u) << start;
    // History row 0 is the start, column by column (the file's 17 digits read back).
    std::ifstream history(dir + "/history.csv");
    std::string header, row;
    std::getline(history, header);
    std::getline(history, row);
    const auto cells = [](const std::string& line) {
        std::vector<std::string> c;
        std::stringstream in(line);
        for (std::string cell; std::getline(in, cell, ',');)
            c.push_back(cell);
        return c;
    };
    const auto names = cells(header), values = cells(row);
    ASSERT_EQ(names.size(), values.size());
    for (const auto& [name, value] : start["parameters"].items()) {
        const auto column = std::find(names.begin(), names.end(), name);
        ASSERT_NE(column, names.end()) << name;
        EXPECT_EQ(std::stod(values[std::size_t(column - names.begin())]), value.get<double>())
            << name;
    }
    EXPECT_TRUE(std::filesystem::exists(dir + "/profiles.png"));
    std::ifstream options_in(dir + "/options.json");
    const auto options = nlohmann::json::parse(options_in);
    EXPECT_EQ(options["start"]["kind"], "tailored");
    EXPECT_EQ(options["start"]["parameters"], start["parameters"]);

    EXPECT_EQ(run("optimize " + scene + " --resume " + dir + " --start tailored").code, 2);
    const auto resumed = run("optimize " + scene + " --resume " + dir + " --json");
    ASSERT_EQ(resumed.code, 0) << resumed.out;
    const auto k = nlohmann::json::parse(resumed.out.substr(resumed.out.find('{')));
    EXPECT_EQ(k["start"]["kind"], "tailored");
    EXPECT_EQ(k["start"]["parameters"], start["parameters"]);
    EXPECT_EQ(k["best_parameters"], j["best_parameters"]);
}

// A ray file source (the writer's, beside its scene): a search over it runs, and its
// best.toml finds the ray file from the output folder (written absolute).
// With a smoothness weight the tailored start chooses its edge ray by the search's score
// (the metric plus the weight x the profile's bending energy), not by the metric alone: the
// report's quick_score is each edge ray's metric plus w x an energy that does not depend on
// w, and the kept one has the lowest score.
TEST(CliOptimize, AWeightedTailoredStartChoosesItsEdgeRayByScore) {
    std::string text;
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/test/profile_search.toml");
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const std::string key = "max_evaluations = 16";
    ASSERT_NE(text.find(key), std::string::npos);
    std::map<double, nlohmann::json> starts;
    for (const double w : {1.0, 1000.0}) {
        std::string weighted = text;
        weighted.replace(weighted.find(key), key.size(),
                         "max_evaluations = 1\nsmoothness = " + std::to_string(w));
        const std::string scene =
            ::testing::TempDir() + "/fird_weighted_tailored_" + std::to_string(int(w)) + ".toml";
        std::ofstream(scene) << weighted;
        const auto r = run("optimize " + scene + " --start tailored --method cmaes --json");
        ASSERT_EQ(r.code, 0) << r.out;
        starts[w] = nlohmann::json::parse(r.out.substr(r.out.find('{'))).at("start");
    }
    for (const auto& [w, start] : starts) {
        const auto& metric = start.at("quick_metric");
        const auto& score = start.at("quick_score");
        ASSERT_EQ(score.size(), metric.size()) << start;
        std::string lowest;
        for (const auto& [edge, value] : score.items()) {
            EXPECT_GE(value.get<double>(), metric.at(edge).get<double>()) << edge;
            if (lowest.empty() || value.get<double>() < score.at(lowest).get<double>())
                lowest = edge;
            // The same energy at both weights (the penalty scales with w).
            const double energy_1 = (starts[1.0].at("quick_score").at(edge).get<double>() -
                                     starts[1.0].at("quick_metric").at(edge).get<double>());
            EXPECT_NEAR((value.get<double>() - metric.at(edge).get<double>()) / w, energy_1,
                        1e-9 * energy_1 * w)
                << edge;
        }
        EXPECT_EQ(start.at("edge_ray").get<std::string>(), lowest) << start;
    }
}

TEST(CliOptimize, ARayFileScenesBestTomlTracesFromItsOutputFolder) {
    const fird::test::RayFiles& files = fird::test::ray_files();
    std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/led_die.toml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    text = text.substr(0, text.find("[source]")) +
           "[source]\ntype = \"rayfile\"\nfile = \"disk.tm25ray\"\ncenter_mm = [0.0, 0.0, "
           "0.0]\nnormal = [0.0, 0.0, -1.0]\n\n" +
           text.substr(text.find("[holder]"));
    const std::string scene = files("led_ray_file.toml");
    std::ofstream(scene) << text;
    const std::string dir = ::testing::TempDir() + "/fird_optimize_ray_file";
    std::filesystem::remove_all(dir);
    const auto r =
        run("optimize " + scene + " --method bobyqa --max-evals 3 --rays 5e4 --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto t = run("trace " + dir + "/best.toml --json --rays 1000");
    ASSERT_EQ(t.code, 0) << t.out;
    const auto j = nlohmann::json::parse(t.out.substr(t.out.find('{')));
    EXPECT_EQ(j["energy_emitted_lm"].get<double>(), 100.0) << "the file's header lumens";
}

TEST(CliOptimize, BadOptionsAreUsageErrorsAndAMissingBoxIsRefused) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    for (const char* bad : {"--method nope", "--rays 0", "--rays 1e5,x", "--max-evals 0",
                            "--threshold -1", "--max-evals -3", "--seed x", "--backend fast"}) {
        const auto r = run("optimize " + scene + " " + bad);
        EXPECT_EQ(r.code, 2) << bad << ": " << r.out;
        EXPECT_NE(r.out.find("error"), std::string::npos) << bad;
    }
    const auto no_box =
        run("optimize " + std::string(FIRD_SOURCE_DIR) + "/scenes/test/flat_mirror.toml");
    EXPECT_EQ(no_box.code, 1) << no_box.out;
    EXPECT_NE(no_box.out.find("[reflector.optimize] is missing"), std::string::npos) << no_box.out;
    EXPECT_EQ(std::count(no_box.out.begin(), no_box.out.end(), '\n'), 1) << no_box.out;
    const auto no_dir = run("optimize " + scene + " --resume /nonexistent/fird");
    EXPECT_EQ(no_dir.code, 1) << no_dir.out;
    EXPECT_NE(no_dir.out.find("options.json"), std::string::npos) << no_dir.out;
    const auto both = run("optimize " + scene + " --resume /tmp --method grid");
    EXPECT_EQ(both.code, 2) << both.out;
    // Refining below the step follows a lattice: after a continuous method it means nothing.
    const auto refine = run("optimize " + scene + " --method bobyqa --refine");
    EXPECT_EQ(refine.code, 2) << refine.out;
    EXPECT_NE(refine.out.find("--refine"), std::string::npos) << refine.out;
}

// --backend cpu: every candidate traced by the CPU reference, said so in the JSON and kept
// in options.json (a resumed search continues on the same tracer).
TEST(CliOptimize, TheCpuBackendJudgesTheSearchAndIsRecorded) {
    const std::string dir = ::testing::TempDir() + "/fird_optimize_cpu";
    std::filesystem::remove_all(dir);
    const auto r = run("optimize " + std::string(FIRD_SOURCE_DIR) +
                       "/scenes/test/mirror_search.toml --json --method grid --rays 5000 "
                       "--backend cpu --out " +
                       dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    EXPECT_EQ(j["backend"], "cpu");
    EXPECT_EQ(j["evaluations"], 169); // the 13 x 13 lattice
    std::ifstream options(dir + "/options.json");
    const auto o = nlohmann::json::parse(options);
    EXPECT_EQ(o["backend"], "cpu");
}

// --refine: the lattice's verdict in the JSON, then a sub-step stage that starts from the
// lattice's best point (BOBYQA's first candidate is its start) and ends no worse than it
// (the same rays score the start as the lattice stage did).
TEST(CliOptimize, RefineReportsTheLatticeAndGoesBelowTheStep) {
    const auto r = run("optimize " + std::string(FIRD_SOURCE_DIR) +
                       "/scenes/test/mirror_search.toml --json --refine");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    ASSERT_TRUE(j["lattice"].is_object()) << j.dump();
    const auto& lattice = j["lattice"];
    EXPECT_EQ(lattice["stage"], "confirm");
    EXPECT_FALSE(lattice["verdict"].get<std::string>().empty());
    EXPECT_EQ(lattice["refined_from"], lattice["point"]);
    EXPECT_EQ(lattice["refine_starts"].front(), lattice["point"]);
    const auto& stages = j["rays_per_evaluation"];
    EXPECT_EQ(stages.back()["stage"], "sub-step");
    EXPECT_LE(stages.back()["best_l2"].get<double>(),
              stages[stages.size() - 2]["best_l2"].get<double>());
}

// A search killed with SIGKILL mid-way and resumed gives what an uninterrupted one gives.
TEST(CliOptimize, KilledSearchResumedEndsWhereAnUninterruptedOneDoes) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    const std::string whole = ::testing::TempDir() + "/fird_whole",
                      cut = ::testing::TempDir() + "/fird_cut";
    std::filesystem::remove_all(whole);
    std::filesystem::remove_all(cut);
    const auto w = run("optimize " + scene + " --method grid --out " + whole);
    ASSERT_EQ(w.code, 0) << w.out;
    // Start it again, wait (bounded) for 40 history rows, kill it hard.
    const std::string kill_script =
        "sh -c '" + std::string(FIRD_BINARY) + " optimize " + scene + " --method grid --out " +
        cut + " >/dev/null 2>&1 & pid=$!; i=0; while [ $i -lt 600 ]; do n=$(cat " + cut +
        "/history.csv 2>/dev/null | wc -l); [ $n -gt 40 ] && break; sleep 0.05; i=$((i+1)); "
        "done; kill -9 $pid; wait $pid; exit 0'";
    ASSERT_EQ(std::system(kill_script.c_str()), 0);
    const auto r = run("optimize " + scene + " --resume " + cut);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto read = [](const std::string& path) {
        std::ifstream in(path);
        return nlohmann::json::parse(in);
    };
    const auto a = read(whole + "/search.json"), b = read(cut + "/search.json");
    EXPECT_EQ(a["best_parameters"], b["best_parameters"]);
    EXPECT_EQ(a["best_l2"], b["best_l2"]);
    EXPECT_EQ(a["final_l2"], b["final_l2"]);
    EXPECT_EQ(a["evaluations"], b["evaluations"]);
    std::ifstream ha(whole + "/history.csv"), hb(cut + "/history.csv");
    std::string la, lb;
    std::size_t rows = 0;
    // Same rows, apart from the ms column (a row's wall time).
    while (std::getline(ha, la) && std::getline(hb, lb)) {
        EXPECT_EQ(la.substr(0, la.rfind(',')), lb.substr(0, lb.rfind(','))) << rows;
        ++rows;
    }
    EXPECT_EQ(rows, 170u);
}

// A search's result depends on the files its scene names, the program and the device:
// --resume refuses (exit 1, one line naming what changed) when one of them differs from
// when the search began, and continues when all are as they were.
TEST(CliOptimize, ResumeIsRefusedWhenANamedFileChanged) {
    const std::string dir =
        (std::filesystem::path(::testing::TempDir()) / "fird_resume_inputs").lexically_normal();
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto read_text = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    // The mirror search with Model A's luminaire file as its desired far field, both copied
    // beside each other so the test may change the file.
    std::string text = read_text(std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml");
    const std::size_t target = text.find("[target]"), after = text.find("[optimize]");
    ASSERT_NE(target, std::string::npos);
    ASSERT_NE(after, std::string::npos);
    text.replace(target, after - target, "[target]\nfile = \"luminaire.ies\"\n\n");
    const std::string scene = dir + "/scene.toml", ies = dir + "/luminaire.ies", out = dir + "/out";
    std::ofstream(scene) << text;
    const std::string luminaire =
        read_text(std::string(FIRD_SOURCE_DIR) + "/scenes/targets/model_a_target.ies");
    std::ofstream(ies, std::ios::binary) << luminaire;
    const auto began =
        run("optimize " + scene + " --method grid --rays 1e4 --max-evals 3 --out " + out);
    ASSERT_EQ(began.code, 0) << began.out;

    // The luminaire file gains one trailing newline: its contents changed.
    std::ofstream(ies, std::ios::binary) << luminaire << "\n";
    auto r = run("optimize " + scene + " --resume " + out);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(
        r.out.find("--resume " + out + ": target " + ies + " has changed since the search began"),
        std::string::npos)
        << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    std::filesystem::remove(ies);
    r = run("optimize " + scene + " --resume " + out);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find(ies + " has changed"), std::string::npos) << r.out;

    // As it was: the resume goes ahead (and replays the three rows).
    std::ofstream(ies, std::ios::binary) << luminaire;
    r = run("optimize " + scene + " --resume " + out);
    EXPECT_EQ(r.code, 0) << r.out;

    // The program and the device, as options.json records them, changed one at a time.
    const std::string options = out + "/options.json";
    const nlohmann::json recorded = nlohmann::json::parse(read_text(options));
    ASSERT_EQ(recorded["depends_on"]["files"].size(), 1u);
    EXPECT_EQ(recorded["depends_on"]["files"][0]["file"], "luminaire.ies");
    const auto refused = [&](const std::function<void(nlohmann::json&)>& change,
                             const std::string& what) {
        nlohmann::json j = recorded;
        change(j);
        std::ofstream(options) << j.dump(2);
        const auto c = run("optimize " + scene + " --resume " + out);
        EXPECT_EQ(c.code, 1) << what << ": " << c.out;
        EXPECT_NE(c.out.find("--resume " + out + ": " + what), std::string::npos) << c.out;
        EXPECT_EQ(std::count(c.out.begin(), c.out.end(), '\n'), 1) << c.out;
    };
    refused([](nlohmann::json& j) { j["depends_on"]["program"] = "0.0.1 (0123456789ab)"; },
            "fird has changed since the search began (0.0.1 (0123456789ab) then");
    refused([](nlohmann::json& j) { j["depends_on"]["device"]["name"] = "another device"; },
            "the device has changed since the search began (another device");
    refused([](nlohmann::json& j) { j["depends_on"]["device"]["driver_info"] = "older"; },
            "the device's driver has changed since the search began");
    refused([](nlohmann::json& j) { j["depends_on"]["device"]["driver_version"] = 0xFFFFFF; },
            "the device's driver has changed since the search began");
    refused([](nlohmann::json& j) { j.erase("depends_on"); },
            "options.json does not record the program");
}

TEST(CliCalibrate, RaysJsonHasTheContractKeysAndOutHasTheTable) {
    const std::string dir = ::testing::TempDir() + "/fird_calibrate_rays";
    const auto r =
        run("calibrate rays " + std::string(FIRD_SOURCE_DIR) +
            "/scenes/test/mirror_search.toml --counts 1e3,1e4 --runs 3 --json --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    for (const char* key : {"rows", "desired_rays", "slope"})
        EXPECT_TRUE(j.contains(key)) << key;
    ASSERT_EQ(j["rows"].size(), 2u);
    for (const char* key : {"rays", "runs", "mean_l2", "var_l2", "predicted_l2", "multinomial_l2",
                            "replicate_l2", "replicate_pairs"})
        EXPECT_TRUE(j["rows"][0].contains(key)) << key;
    // The scene's sampler (the stratified default) and the prediction made for it.
    EXPECT_EQ(j["sampler"], "stratified");
    EXPECT_EQ(j["prediction"], "replicate");
    EXPECT_EQ(j["rows"][0]["predicted_l2"], j["rows"][0]["replicate_l2"]);
    for (const char* name : {"table1.csv", "table1.md", "table1.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + name)) << name;
}

TEST(CliCalibrate, SemivariogramWritesStepsThatTraceAndRefusesBadInput) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    const std::string dir = ::testing::TempDir() + "/fird_calibrate_sv";
    const std::string steps = ::testing::TempDir() + "/fird_calibrated.toml";
    const auto r = run("calibrate semivariogram " + scene + " --points 9 --rays 1e4 --json --out " +
                       dir + " --write-steps " + steps);
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["parameters"].size(), 2u);
    EXPECT_GT(j["noise_variance_l2"].get<double>(), 0.0);
    for (const char* key : {"series", "lags", "gamma", "pairs", "model", "recommended_step",
                            "resolvable_step", "resolution", "calibrated_step"})
        EXPECT_TRUE(j["parameters"][0].contains(key)) << key;
    EXPECT_EQ(j["step_rule"], "resolvable"); // the default
    EXPECT_EQ(j["ordering_confidence"], 0.95);
    for (const char* key : {"type", "nugget", "sill", "range"})
        EXPECT_TRUE(j["parameters"][0]["model"].contains(key)) << key;
    for (const char* name : {"series.csv", "semivariogram.csv", "resolution.csv",
                             "semivariogram_sx.png", "semivariogram_sy.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + name)) << name;
    EXPECT_EQ(run("trace " + steps + " --rays 1000").code, 0);
    // The default (resolvable) rule writes the smallest step a search resolves: below the
    // range the paper's rule writes.
    const std::string coarse = ::testing::TempDir() + "/fird_calibrated_coarse.toml";
    ASSERT_EQ(run("calibrate semivariogram " + scene +
                  " --parameter sx --points 9 --rays 1e4 --step-rule range --write-steps " + coarse)
                  .code,
              0);
    EXPECT_LT(fird::load_scene(steps).reflector.optimize.at("sx").step,
              fird::load_scene(coarse).reflector.optimize.at("sx").step);
    for (const char* bad :
         {"--parameter z0", "--points 2", "--rays 0", "--points x", "--step-rule widest"}) {
        const auto b = run("calibrate semivariogram " + scene + " " + bad);
        EXPECT_EQ(b.code, 2) << bad << ": " << b.out;
    }
    const auto c = run("calibrate rays " + scene + " --counts 1e3,0");
    EXPECT_EQ(c.code, 2) << c.out;
    EXPECT_NE(c.out.find("--counts"), std::string::npos) << c.out;
}

// The manufacturability report of Model A's target paraboloid (fx 15, fy 10, z0 -12) with
// a slope limit it breaks: its keys, its closed forms (depth 12 mm to the clamp at the top,
// smallest radius 2 fy at the apex, walls 2 mm tall where y = +-20 stays below the top),
// and the steepest slope, on the crease where it meets the rim (x^2 / 60 = 2, y = 20:
// atan sqrt(1 + 120 / 900)), within the sampling error the report states.
TEST(CliExport, ManufacturabilityReportHasTheClosedFormsAndTheConstraints) {
    const std::string dir = ::testing::TempDir() + "/fird_press_cli";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string scene = dir + "/pressed.toml";
    {
        std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/model_a.toml");
        std::ofstream out(scene);
        out << in.rdbuf() << "\n[reflector.constraints]\nmax_slope_deg = 40.0\nmax_depth_mm = 15\n";
    }
    const auto r = run("export " + scene + " --parameters fx=15,fy=10,z0=-12 --manufacturability " +
                       dir + "/press --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    EXPECT_TRUE(j["cad"].is_null());
    const auto& m = j["manufacturability"];
    for (const char* key : {"max_slope_deg", "max_slope_at_mm", "min_radius_mm", "min_radius_at_mm",
                            "depth_mm", "area_mm2", "rim_walls", "constraints"})
        EXPECT_TRUE(m.contains(key)) << key;
    EXPECT_NEAR(m["depth_mm"].get<double>(), 12.0, 1e-9);
    EXPECT_NEAR(m["min_radius_mm"].get<double>(), 20.0, 1e-9);
    ASSERT_EQ(m["rim_walls"].size(), 2u);
    EXPECT_NEAR(m["rim_walls"][0]["height_mm"].get<double>(), 2.0, 1e-9);
    const double steepest = std::atan(std::sqrt(1.0 + 120.0 / 900.0)) * 180.0 / std::numbers::pi;
    EXPECT_LE(m["max_slope_deg"].get<double>(), steepest + 1e-9);
    EXPECT_GE(m["max_slope_deg"].get<double>() + m["sampling"]["slope_error_deg"].get<double>(),
              steepest);
    EXPECT_NEAR(std::abs(m["max_slope_at_mm"][1].get<double>()), 20.0, 0.2);
    EXPECT_EQ(m["constraints"]["max_slope_deg"]["met"], false);
    EXPECT_EQ(m["constraints"]["max_slope_deg"]["limit"], 40.0);
    EXPECT_EQ(m["constraints"]["max_depth_mm"]["met"], true);
    EXPECT_FALSE(m["constraints"].contains("min_radius_mm"));
    for (const char* name : {"manufacturability.json", "manufacturability.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/press/" + name)) << name;
    // --cad writes the report beside reflector.step.
    const auto cad =
        run("export " + std::string(FIRD_SOURCE_DIR) +
            "/scenes/test/mirror_search.toml --parameters sx=0.1,sy=0 --cad " + dir + "/cad");
    ASSERT_EQ(cad.code, 0) << cad.out;
    EXPECT_NE(cad.out.find("steepest slope 5.71 deg"), std::string::npos) << cad.out;
    for (const char* name : {"reflector.step", "manufacturability.json", "manufacturability.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/cad/" + name)) << name;
}

TEST(CliExport, WritesEveryFileAndRefusesBadValues) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    const std::string dir = ::testing::TempDir() + "/fird_export_cli";
    const auto r = run("export " + scene + " --paths 20 --parameters sx=0.1 --out " + dir);
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* name : {"reflector.vts", "quadtree.vtu", "rays.vtp", "farfield.vti",
                             "farfield_sphere.vtp", "source.vtp", "holder.vtp", "scene.pvd"}) {
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + name)) << name;
        EXPECT_NE(r.out.find(name), std::string::npos) << name; // sizes are reported
    }
    for (const char* bad : {"--parameters sx", "--paths -1", "--rays 0", "--levels x"}) {
        const auto b = run("export " + scene + " " + bad + " --out " + dir);
        EXPECT_EQ(b.code, 2) << bad << ": " << b.out;
    }
    const auto unknown = run("export " + scene + " --parameters nope=1 --out " + dir);
    EXPECT_EQ(unknown.code, 1) << unknown.out;
    EXPECT_NE(unknown.out.find("nope"), std::string::npos) << unknown.out;
    const auto cuts = run("export " + scene + " --parameters z0=5.5 --out " + dir);
    EXPECT_EQ(cuts.code, 1) << cuts.out;
    EXPECT_NE(cuts.out.find("cuts the light source"), std::string::npos) << cuts.out;
}

// What a process loads (docs/architecture.md "Start-up"), from the dynamic loader's own
// account of the files it opens (glibc's LD_DEBUG=files): a trace opens neither VTK nor
// OpenCASCADE nor pagmo, nor FIRD's modules for them; an export opens its own module and
// the library behind it, and not the other's.
TEST(CliExport, EachExportLoadsItsOwnLibraryAndATraceNeither) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";
    const std::string dir = ::testing::TempDir() + "/fird_export_loads";
    std::filesystem::remove_all(dir);
    // Whether a "file=PATH" of the account names a file whose name begins with `file`.
    const auto opened = [](const fird::test::Result& r, const std::string& file) {
        std::istringstream lines(r.out);
        for (std::string line; std::getline(lines, line);) {
            const auto at = line.find("file=");
            if (at == std::string::npos) continue;
            const std::string path = line.substr(at + 5, line.find(' ', at) - at - 5);
            if (path.substr(path.rfind('/') + 1).starts_with(file)) return true;
        }
        return false;
    };
    const auto trace =
        fird::test::run_fird("LD_DEBUG=files timeout 120", "trace " + scene + " --rays 1e4");
    ASSERT_EQ(trace.code, 0) << trace.out;
    ASSERT_TRUE(opened(trace, "libvulkan.so")) << trace.out; // the account is there
    for (const char* file : {"libfird_vtk.so", "libvtkCommonCore", "libfird_cad.so", "libTKernel",
                             "libfird_pagmo.so", "libpagmo"})
        EXPECT_FALSE(opened(trace, file)) << file;
    struct Export {
        std::string args, module, library, other_module, other_library, file;
    };
    for (const Export& e :
         {Export{"--rays 1e4 --out " + dir + "/vtk", "libfird_vtk.so", "libvtkCommonCore",
                 "libfird_cad.so", "libTKernel", dir + "/vtk/scene.pvd"},
          Export{"--cad " + dir + "/cad", "libfird_cad.so", "libTKernel", "libfird_vtk.so",
                 "libvtkCommonCore", dir + "/cad/reflector.step"}}) {
        const auto r =
            fird::test::run_fird("LD_DEBUG=files timeout 120", "export " + scene + " " + e.args);
        ASSERT_EQ(r.code, 0) << r.out;
        EXPECT_TRUE(opened(r, e.module) && opened(r, e.library)) << e.args;
        EXPECT_FALSE(opened(r, e.other_module) || opened(r, e.other_library)) << e.args;
        EXPECT_TRUE(std::filesystem::is_regular_file(e.file)) << e.file;
    }
}

TEST(CliScreenshot, WritesTheViewsAndRefusesBadValues) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/focused_paraboloid.toml";
    const std::string dir = ::testing::TempDir() + "/fird_screenshot";
    const auto r = run("screenshot " + scene + " --out " + dir +
                       " --size 320x200 --rays 2e4 --pick-ray 3 --camera 30,40,120");
    ASSERT_EQ(r.code, 0) << r.out;
    for (const char* name : {"viewport.png", "farfield.png", "plots.png", "polar.png",
                             "isocandela.png", "illuminance.png"})
        EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/" + name)) << name;
    for (const char* bad :
         {"--size 320", "--size 10x10", "--size axb", "--view sideways", "--camera 1,2",
          "--plane-distance 0", "--plane-distance nan", "--camera 0,95,10", "--camera 0,10,-5",
          "--camera a,b,c", "--pick-ray -1"}) {
        const auto b = run("screenshot " + scene + " --out " + dir + " " + bad);
        EXPECT_EQ(b.code, 2) << bad << ": " << b.out;
    }
    const auto pick =
        run("screenshot " + scene + " --out " + dir + " --rays 2e4 --pick-ray 100000");
    EXPECT_EQ(pick.code, 1) << pick.out;
    EXPECT_NE(pick.out.find("--pick-ray"), std::string::npos) << pick.out;
}

// --pick-ray INDEX --json: the picked ray's path and its walk, each step with the keys
// docs/workbench.md names; the first bounce's walk ends with a hit at the distance from
// the ray's origin to the path's first hit vertex (the trace's hit record, not the walk's).
TEST(CliScreenshot, JsonGivesThePickedRaysPathAndWalk) {
    const std::string scene = std::string(FIRD_SOURCE_DIR) + "/scenes/test/focused_paraboloid.toml";
    const std::string dir = ::testing::TempDir() + "/fird_screenshot_json";
    // Ray 150000 of 2e5 runs nearly level from the source to the paraboloid's wall: its
    // walk ascends, advances and descends on the way.
    const auto r = run("screenshot " + scene + " --out " + dir +
                       " --view viewport --size 320x200 --pick-ray 150000 --json");
    ASSERT_EQ(r.code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
    ASSERT_TRUE(j.contains("picked_ray")) << r.out;
    const auto& p = j["picked_ray"];
    EXPECT_EQ(p["index"], 150000);
    ASSERT_GE(p["path_mm"].size(), 3u);
    ASSERT_FALSE(p["walk"].empty());
    for (const auto& s : p["walk"])
        for (const char* key : {"bounce", "level", "node", "t_mm", "t_exit_mm", "ray_z_mm",
                                "ray_z_exit_mm", "node_max_mm", "decision", "t_next_mm", "why"})
            EXPECT_TRUE(s.contains(key)) << key;
    const auto& last = p["walk"].back();
    EXPECT_EQ(last["bounce"], 0);
    EXPECT_EQ(last["decision"], "hit");
    double d = 0.0;
    for (int k = 0; k < 3; ++k)
        d += std::pow(p["path_mm"][1][k].get<double>() - p["origin_mm"][k].get<double>(), 2);
    // Float t and float hit coordinates of ~10 mm: 1e-4 mm.
    EXPECT_NEAR(last["t_next_mm"].get<double>(), std::sqrt(d), 1e-4);
}

#if FIRD_HAS_UI
// A bad script line is refused naming the file and line, before any window opens.
TEST(CliGui, ABadScriptLineIsAnErrorNamingFileAndLine) {
    const std::string path = ::testing::TempDir() + "/bad_session.fird";
    for (const auto& [text, where] :
         std::vector<std::pair<std::string, std::string>>{{"# ok\nfrobnicate\n", ":2:"},
                                                          {"open\n", ":1:"},
                                                          {"trace\nset sx fast\n", ":2:"},
                                                          {"wait -3\n", ":1:"},
                                                          {"optimize newton\n", ":1:"},
                                                          {"calibrate everything\n", ":1:"},
                                                          {"trace\ndrag 1 2 3\n", ":2:"},
                                                          {"drag 1 2 3 4 middle\n", ":1:"},
                                                          {"resize 100 650\n", ":1:"},
                                                          {"wait 1\nresize 1000 6.5e2x\n", ":2:"},
                                                          {"pick-ray 1.5\n", ":1:"},
                                                          {"trace\npick-ray -3\n", ":2:"}}) {
        std::ofstream(path) << text;
        const auto r = run("gui --script " + path);
        EXPECT_NE(r.code, 0) << text;
        EXPECT_NE(r.out.find(path + where), std::string::npos) << text << r.out;
    }
    const auto missing = run("gui --script /nonexistent/session.fird");
    EXPECT_NE(missing.code, 0);
    EXPECT_NE(missing.out.find("/nonexistent/session.fird"), std::string::npos) << missing.out;
}
#endif
