// Bad input, everywhere: every command refuses malformed and out-of-range values,
// unreadable and missing files, a directory where a file belongs and an output it cannot
// write, with one line naming the file, key or option and the exit code the README gives
// (2 usage, 1 runtime), in bounded time, never a crash.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <sys/wait.h>
#include <vector>

#include <gtest/gtest.h>

#include <fmt/format.h>

#include "io/ray_files_fixture.hpp"
#include "run_fird.hpp"

namespace {

namespace fs = std::filesystem;

using fird::test::Result;

// Bounded: a hang fails the row (timeout's code 124) instead of the suite.
Result run(const std::string& args) {
    return fird::test::run_fird("timeout 120", args);
}

std::string dir() {
    static const std::string d = [] {
        const fs::path p = fs::path(::testing::TempDir()) / "fird_bad_input";
        fs::create_directories(p);
        return p.string();
    }();
    return d;
}

// A scene file from the flat mirror with one line replaced (or appended).
std::string scene_with(const std::string& name, const std::string& from, const std::string& to) {
    std::ifstream in(std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!from.empty()) {
        const auto at = text.find(from);
        if (at == std::string::npos)
            ADD_FAILURE() << "no '" << from << "' in the scene";
        else
            text.replace(at, from.size(), to);
    } else {
        text += to;
    }
    const std::string path = dir() + "/" + name + ".toml";
    std::ofstream(path) << text;
    return path;
}

struct Row {
    std::string args;
    int code;
    std::string says; // a text the one line must contain
};

void check(const std::vector<Row>& rows) {
    for (const Row& r : rows) {
        const Result res = run(r.args);
        EXPECT_EQ(res.code, r.code) << r.args << "\n" << res.out;
        EXPECT_NE(res.out.find(r.says), std::string::npos) << r.args << "\n" << res.out;
        // One line (a usage error adds the usage line); no Vulkan validation noise.
        EXPECT_LE(std::count(res.out.begin(), res.out.end(), '\n'), r.code == 2 ? 2 : 1)
            << r.args << "\n"
            << res.out;
    }
}

const std::string good = std::string(FIRD_SOURCE_DIR) + "/scenes/test/mirror_search.toml";

TEST(BadInput, SceneFilesNamingFileLineAndKey) {
    check({
        {"trace " + scene_with("nan", "sx = -0.25", "sx = nan"), 1, "sx: must be finite"},
        {"trace " + scene_with("inf", "z0 = -2.0", "z0 = inf"), 1, "z0: must be finite"},
        {"trace " + scene_with("zero_rays", "rays = 40000", "rays = 0"), 1,
         "rays: must be between"},
        {"trace " + scene_with("neg_bounces", "max_bounces = 1", "max_bounces = -1"), 1,
         "max_bounces"},
        {"trace " + scene_with("zero_grid", "farfield = [180, 90]", "farfield = [0, 90]"), 1,
         "farfield"},
        {"trace " + scene_with("cuts", "z0 = -2.0", "z0 = 5.5"), 1, "cuts the light source"},
        {"trace " +
             scene_with("outside", "center_mm = [0.0, 0.0, 5.0]", "center_mm = [50.0, 0.0, 5.0]"),
         1, "outside the holder"},
        {"trace " + scene_with("unknown", "", "\n[trace2]\nx = 1\n"), 1, "trace2: unknown key"},
        {"trace " +
             scene_with("big_grid", "heightfield = [64, 64]", "heightfield = [16384, 16384]"),
         1, "heightfield 16384 x 16384"},
        {"trace /nonexistent/scene.toml", 1, "/nonexistent/scene.toml: cannot open"},
        {"trace " + dir(), 1, dir()},
    });
}

TEST(BadInput, OptionValuesOfEveryCommand) {
    check({
        {"trace " + good + " --rays 0", 2, "--rays"},
        {"trace " + good + " --rays nan", 2, "--rays"},
        {"trace " + good + " --rays 2.5", 2, "--rays"},
        {"trace " + good + " --backend quantum", 2, "--backend"},
        {"optimize " + good + " --rays inf", 2, "--rays"},
        {"optimize " + good + " --threshold nan", 2, "--threshold"},
        {"optimize " + good + " --method newton", 2, "--method"},
        {"calibrate rays " + good + " --runs 0", 2, "--runs"},
        {"calibrate rays " + good + " --counts 1e3,-5", 2, "--counts"},
        {"calibrate semivariogram " + good + " --points 1", 2, "--points"},
        {"calibrate semivariogram " + good + " --parameter q", 2, "--parameter q"},
        {"export " + good + " --paths 2000000", 2, "--paths"},
        {"export " + good + " --parameters sx=nan", 2, "--parameters"},
        {"export " + good + " --levels 99", 2, "--levels"},
        {"screenshot " + good + " --out " + dir() + " --size 0x0", 2, "--size"},
        {"screenshot " + good + " --out " + dir() + " --camera 1,nan,2", 2, "--camera"},
        {"screenshot " + good + " --out " + dir() + " --slope-colours --curvature-colours", 2,
         "--slope-colours excludes --curvature-colours"},
        {"bench --rays 0", 2, "--rays"},
        {"bench --heightfields 0x5", 2, "--heightfields"},
        {"photometry convert " + std::string(FIRD_SOURCE_DIR) +
             "/tests/photometry/data/corpus/luxpy_pair_quadrant.ies " + dir() + "/b.xyz",
         1, "b.xyz"},
        {"stress --case no-such-case", 1, "no such case"},
        {"tolerance " + good + " --realisations 0 --reflectance-sd 0.01", 2, "--realisations"},
        {"tolerance " + good + " --reflectance-sd -0.1", 2, "--reflectance-sd"},
        {"tolerance " + good + " --source-shift-mm 1,2", 2, "--source-shift-mm"},
        {"tolerance " + good + " --surface-rms-mm 0.01", 2, "--surface-correlation-mm"},
        {"tolerance " + good, 2, "no tolerance given"},
        {"tolerance " + good + " --reflectance-sd 0.01 --out /proc/fird_no", 1, "/proc/fird_no"},
        {"--max-device-memory 0 info", 2, "--max-device-memory"},
        {"--max-device-memory nan info", 2, "--max-device-memory: 'nan' is not a finite number"},
        {"--max-device-memory inf info", 2, "--max-device-memory"},
        {"--max-batch-rays 0 info", 2, "--max-batch-rays"},
        {"--max-batch-rays -5 info", 2, "--max-batch-rays"},
        // Device out of memory (provoked with the budget) says what to lower.
        {"--max-device-memory 50 trace " + std::string(FIRD_SOURCE_DIR) + "/scenes/model_a.toml", 1,
         "out of device memory"},
    });
}

TEST(BadInput, FilesThatAreMissingUnreadableOrDirectories) {
    const std::string ies = dir() + "/broken.ies";
    std::ofstream(ies) << "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 x\n";
    check({
        {"photometry info /nonexistent/x.ies", 1, "/nonexistent/x.ies"},
        {"photometry info " + ies, 1, "broken.ies"},
        {"photometry info " + dir(), 1, dir()},
        {"optimize " + good + " --resume " + dir(), 1, "options.json"},
    });
#if FIRD_HAS_UI
    // A script line refused before any window opens: the file and the line named.
    const std::string script = dir() + "/bad_tolerance.fird";
    std::ofstream(script) << "# a form field without its value\ntolerance realisations\n";
    check({{"gui --script " + dir(), 1, dir()},
           {"gui --script " + script, 1,
            "bad_tolerance.fird:2: tolerance (start) or tolerance KEY VALUE"},
           // An offscreen frame's size, refused before anything opens.
           {"gui --offscreen 100x100", 2, "--offscreen 100x100: at least 200x200"},
           {"gui --offscreen wide", 2, "--offscreen wide: not WxH"}});
#endif
    // A photometric target that is broken, and a mesh that is missing.
    const std::string target = dir() + "/ies_target.toml";
    {
        std::ifstream in(good);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        text = text.substr(0, text.find("[target]")) + "[target]\nfile = \"broken.ies\"\n";
        std::ofstream(target) << text;
    }
    check({{"trace " + target + " --rays 1000", 1, "broken.ies"}});
}

// A ray file source whose file is broken (tests/io/write_ray_files.py put each fault at a
// byte it records): one line naming the scene's key, the ray file and the byte, exit 1.
TEST(BadInput, RayFilesNamingTheFileAndTheByte) {
    const fird::test::RayFiles& files = fird::test::ray_files();
    const auto scene = [&](const std::string& name) {
        return scene_with("rayfile_" + name,
                          "type = \"point\"\ncenter_mm = [0.0, 0.0, 5.0]\nemittance = "
                          "\"cosine\"\naxis = [0.0, 0.0, -1.0]",
                          "type = \"rayfile\"\ncenter_mm = [0.0, 0.0, 5.0]\nfile = \"" +
                              files(name) + "\"");
    };
    const auto byte = [&](const char* key) {
        return fmt::format("byte {}", files.manifest[key]["byte"].get<int>());
    };
    check({
        {"trace " + scene("short.tm25ray") + " --rays 1000", 1, "short.tm25ray: " + byte("short")},
        {"trace " + scene("bad_tag.tm25ray") + " --rays 1000", 1, "bad_tag.tm25ray: byte 0"},
        {"trace " + scene("size_mismatch.tm25ray") + " --rays 1000", 1,
         "size_mismatch.tm25ray: " + byte("size_mismatch")},
        {"trace " + scene("nan_direction.tm25ray") + " --rays 1000", 1,
         "nan_direction.tm25ray: " + byte("nan_direction")},
        {"optimize " + scene("negative_flux.tm25ray"), 1,
         "negative_flux.tm25ray: " + byte("negative_flux")},
        {"trace " + scene("zero_direction.npy") + " --rays 1000", 1,
         "zero_direction.npy: " + byte("zero_direction")},
        {"trace " + scene("nan_direction.csv") + " --rays 1000", 1, "nan_direction.csv: line 6"},
    });
}

TEST(BadInput, OutputsThatCannotBeWritten) {
    // A regular file stands where the output directory should be.
    const std::string blocker = dir() + "/a_file";
    std::ofstream(blocker) << "x";
    const std::string out = blocker + "/out";
    check({
        {"trace " + good + " --rays 1000 --out " + out, 1, out},
        {"optimize " + good + " --max-evals 2 --out " + out, 1, out},
        {"export " + good + " --rays 1000 --out " + out, 1, out},
        {"screenshot " + good + " --rays 1000 --view plots --out " + out, 1, out},
        {"calibrate rays " + good + " --counts 1e3 --runs 2 --out " + out, 1, out},
        {"stress --case grazing --out " + out, 1, out},
    });
}

// lavapipe at 512-bit vectors (LP_NATIVE_VECTOR_WIDTH: the user's environment, which
// lavapipe honours on any x86 CPU, or FIRD's choice for a command that only computes on a
// CPU with AVX-512) compiles compute shaders but crashes LLVM on a fragment shader (Mesa
// 22.3; docs/architecture.md, "CPU vector width"). A screenshot's viewport draws, so does
// the workbench: each is refused in one line naming the variable, exit 1, with nothing
// written (from an empty shader cache, which could otherwise hold a variant compiled at
// another width). A mesh reflector's raster is a compute pass: its trace runs, as an
// analytic reflector's does.
TEST(BadInput, LavapipeAt512BitsRefusesToDrawInOneLineAndStillTraces) {
    const std::string src = FIRD_SOURCE_DIR;
    const std::string cache = dir() + "/shader_cache_512";
    fs::remove_all(cache);
    fs::remove_all(dir() + "/bits_512");
    const std::string env =
        "timeout 120 env MESA_SHADER_CACHE_DIR=" + cache + " LP_NATIVE_VECTOR_WIDTH=512";
    std::vector<std::string> drawing = {"--device llvmpipe screenshot " + src +
                                        "/scenes/model_a.toml --rays 1e4 --out " + dir() +
                                        "/bits_512"};
#if FIRD_HAS_UI
    drawing.push_back("--device llvmpipe gui --offscreen 200x200 --frames 3");
#endif
    for (const std::string& args : drawing) {
        const auto r = fird::test::run_fird(env, args);
        EXPECT_EQ(r.code, 1) << args << "\n" << r.out;
        EXPECT_NE(r.out.find("fird: error: lavapipe at 512 bits (LP_NATIVE_VECTOR_WIDTH=512) "
                             "cannot compile fragment shaders"),
                  std::string::npos)
            << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
        EXPECT_FALSE(fs::exists(dir() + "/bits_512"));
    }
    for (const char* scene : {"/scenes/test/mesh_dish.toml", "/scenes/model_a.toml"}) {
        const auto traced = fird::test::run_fird(env, "--device llvmpipe trace " + src + scene +
                                                          " --rays 1e4 --json");
        EXPECT_EQ(traced.code, 0) << scene << "\n" << traced.out;
        EXPECT_NE(traced.out.find("512 bits"), std::string::npos) << traced.out;
    }
}

// A copy of fird in DIR/lone/bin with the given modules of this build in DIR/lone/lib (a
// program moved with some of its modules or none); returns the folder as the program sees
// itself (/proc/self/exe: no symbolic link in the path).
fs::path lone_fird(const std::string& name, std::initializer_list<const char*> modules) {
    const fs::path lone = fs::path(dir()) / name;
    fs::remove_all(lone);
    fs::create_directories(lone / "bin");
    fs::create_directories(lone / "lib");
    fs::copy_file(FIRD_BINARY, lone / "bin" / "fird");
    const fs::path built_lib = fs::path(FIRD_BINARY).parent_path().parent_path() / "lib";
    for (const char* module : modules)
        fs::copy_file(built_lib / module, lone / "lib" / module);
    return fs::canonical(lone);
}

// A copy of fird without pagmo's module beside it (a program moved without it): a population
// search, which needs FIRD's pagmo module, is refused in one line naming the
// module and where it was looked for, exit 1, before anything is written; every other
// command runs, pagmo never being loaded at start (a trace and an NLopt search here).
TEST(BadInput, APopulationSearchWithoutItsModuleFailsInOneLineAndOtherCommandsRun) {
    const std::string src = FIRD_SOURCE_DIR;
    // The exports' modules beside it (a search's --out folder needs them), pagmo's not: each
    // module is found or missed on its own.
    const fs::path lone = lone_fird("lone_fird", {"libfird_vtk.so", "libfird_cad.so"});
    const std::string fird = (lone / "bin" / "fird").string();
    const std::string scene = src + "/scenes/model_b.toml";
    for (const char* method : {"cmaes", "xnes"}) {
        const std::string out = (lone / method).string();
        const auto r = fird::test::run_shell(fmt::format(
            "timeout 120 {} --validation optimize {} --method {} --rays 1e4 --max-evals 8 --out {}",
            fird, scene, method, out));
        EXPECT_EQ(r.code, 1) << r.out;
        EXPECT_NE(r.out.find(fmt::format("fird: error: cannot load FIRD's module libfird_pagmo.so "
                                         "(looked for {}, {}): not found",
                                         (lone / "lib" / "libfird_pagmo.so").string(),
                                         (lone / "bin" / "libfird_pagmo.so").string())),
                  std::string::npos)
            << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
        EXPECT_FALSE(fs::exists(out)) << method;
    }
    const auto traced = fird::test::run_shell(
        fmt::format("timeout 120 {} --validation trace {} --rays 1e4 --json", fird, scene));
    EXPECT_EQ(traced.code, 0) << traced.out;
    const auto lattice_free = fird::test::run_shell(fmt::format(
        "timeout 120 {} --validation optimize {} --method bobyqa --rays 1e4 --max-evals 3 --out {}",
        fird, scene, (lone / "bobyqa").string()));
    EXPECT_EQ(lattice_free.code, 0) << lattice_free.out;
    EXPECT_TRUE(fs::exists(lone / "bobyqa" / "search.json"));
}

// A copy of fird with no modules beside it: an export (VTK's files, the CAD part) and a
// search that writes a folder (its reflectors.pvd and the best part's CAD) are refused in
// one line naming the module and where it was looked for, exit 1, before any file; a trace
// and a search without a folder run, neither VTK nor OpenCASCADE being loaded at start.
TEST(BadInput, AnExportWithoutItsModuleFailsInOneLineAndOtherCommandsRun) {
    const std::string src = FIRD_SOURCE_DIR;
    const fs::path lone = lone_fird("lone_fird_exports", {});
    const std::string fird = (lone / "bin" / "fird").string();
    const std::string scene = src + "/scenes/test/mirror_search.toml";
    const auto missing = [&](const char* module) {
        return fmt::format("fird: error: cannot load FIRD's module {} (looked for {}, {}): not "
                           "found",
                           module, (lone / "lib" / module).string(),
                           (lone / "bin" / module).string());
    };
    struct Refused {
        std::string args, module, out;
    };
    const std::string vtk_out = (lone / "vtk").string(), cad_out = (lone / "cad").string(),
                      search_out = (lone / "search").string();
    for (const Refused& c :
         {Refused{fmt::format("export {} --rays 1e4 --out {}", scene, vtk_out), "libfird_vtk.so",
                  vtk_out},
          Refused{fmt::format("export {} --cad {}", scene, cad_out), "libfird_cad.so", cad_out},
          Refused{fmt::format("optimize {} --method bobyqa --rays 1e4 --max-evals 3 --out {}",
                              scene, search_out),
                  "libfird_vtk.so", search_out}}) {
        const auto r =
            fird::test::run_shell(fmt::format("timeout 120 {} --validation {}", fird, c.args));
        EXPECT_EQ(r.code, 1) << c.args << "\n" << r.out;
        EXPECT_NE(r.out.find(missing(c.module.c_str())), std::string::npos) << r.out;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
        EXPECT_FALSE(fs::exists(c.out)) << c.args;
    }
    const auto traced = fird::test::run_shell(
        fmt::format("timeout 120 {} --validation trace {} --rays 1e4 --json", fird, scene));
    EXPECT_EQ(traced.code, 0) << traced.out;
    const auto searched = fird::test::run_shell(fmt::format(
        "timeout 120 {} --validation optimize {} --method bobyqa --rays 1e4 --max-evals 3 --json",
        fird, scene));
    EXPECT_EQ(searched.code, 0) << searched.out;
}

// A module from another build (its engine headers' SHA-256, the table's stamp, not the
// program's: here this build's module with one digit of the stamp changed) is refused in one
// line naming it, exit 1, before the export writes anything.
TEST(BadInput, AModuleFromAnotherBuildIsRefusedInOneLine) {
    const fs::path lone = lone_fird("lone_fird_other_build", {"libfird_cad.so"});
    const fs::path module = lone / "lib" / "libfird_cad.so";
    std::string bytes;
    {
        std::ifstream in(module, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    // The stamp: the module's one run of 64 lowercase hexadecimal digits.
    const auto hex = [](char c) { return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'); };
    std::size_t at = std::string::npos, run = 0;
    for (std::size_t i = 0; i < bytes.size() && at == std::string::npos; ++i) {
        run = hex(bytes[i]) ? run + 1 : 0;
        if (run == 64 && (i + 1 == bytes.size() || bytes[i + 1] == '\0')) at = i - 63;
    }
    ASSERT_NE(at, std::string::npos) << "no stamp in " << module;
    bytes[at] = bytes[at] == '0' ? '1' : '0';
    std::ofstream(module, std::ios::binary | std::ios::trunc) << bytes;
    const std::string out = (lone / "cad").string();
    const auto r = fird::test::run_shell(
        fmt::format("timeout 120 {} export {}/scenes/test/mirror_search.toml --cad {}",
                    (lone / "bin" / "fird").string(), FIRD_SOURCE_DIR, out));
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("fird: error: FIRD's module libfird_cad.so is from another build"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_FALSE(fs::exists(out));
}

} // namespace
