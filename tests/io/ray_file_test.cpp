// Ray files (issue 25 item 3): the readers of TM-25, .npy and CSV read what an independent
// writer (tests/io/write_ray_files.py) wrote, the quirks of published files included; every
// refusal names the file and the byte (CSV: the line) where the writer put the fault; the
// resampling to the emission count is unbiased and independent of batching.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include <fmt/format.h>

#include "io/ray_file.hpp"
#include "io/scene_file.hpp"
#include "io/tm25_file.hpp"
#include "model/ray_file_source.hpp"
#include "model/surface.hpp"
#include "ray_files_fixture.hpp"
#include "reference/reference_tracer.hpp"

namespace fird::test {
namespace {

std::vector<RayRecord> read_all(const RayFileIndex& index) {
    RayFileReader reader(index.layout);
    std::vector<RayRecord> rays;
    for (RayRecord r; reader.next(r);)
        rays.push_back(r);
    return rays;
}

// A scene around a ray file: the file and the [source] and [trace] lines given.
Scene ray_file_scene(const std::string& file, const std::string& source_lines,
                     const std::string& trace_lines = "") {
    return parse_scene(fmt::format(R"(
[source]
type = "rayfile"
file = "{}"
center_mm = [0.0, 0.0, 0.0]
{}
[holder]
min_mm = [-100.0, -100.0, -12.0]
max_mm = [100.0, 100.0, 2.0]
[reflector]
family = "plane"
z0 = -10.0
sx = 0.0
sy = 0.0
cx = 0.0
cy = 0.0
[trace]
seed = 3
max_bounces = 1
{}
)",
                                   file, source_lines, trace_lines),
                       ray_files()("scene.toml"));
}

// The same 3000 rays as TM-25 (luminous flux per ray), npy float64 (no flux), npy float32
// (with flux) and CSV (columns in another order): every value the same, bit for bit (the
// writer wrote float32 values; CSV holds their shortest decimal repr, read back exactly).
TEST(RayFile, Tm25NpyAndCsvReadTheSameRays) {
    const auto tm25 = index_ray_file(ray_files()("part.tm25ray"));
    const std::vector<RayRecord> want = read_all(*tm25);
    ASSERT_EQ(want.size(), 3000u);
    EXPECT_NEAR(tm25->file_flux_lm, ray_files().manifest["part"]["flux_lm"].get<double>(), 1e-9);
    for (const char* name : {"part.npy", "part_flux.npy", "part.csv"}) {
        SCOPED_TRACE(name);
        const auto index = index_ray_file(ray_files()(name));
        const std::vector<RayRecord> got = read_all(*index);
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t i = 0; i < got.size(); ++i) {
            ASSERT_EQ(got[i].position_mm, want[i].position_mm) << "ray " << i;
            ASSERT_EQ(got[i].direction, want[i].direction) << "ray " << i;
        }
    }
    // 0.01 lm a ray: float32 in the npy (as in TM-25), decimal in the CSV; none in part.npy.
    EXPECT_NEAR(index_ray_file(ray_files()("part_flux.npy"))->file_flux_lm, tm25->file_flux_lm,
                1e-9);
    EXPECT_NEAR(index_ray_file(ray_files()("part.csv"))->file_flux_lm, 30.0, 1e-9);
    EXPECT_TRUE(std::isnan(index_ray_file(ray_files()("part.npy"))->file_flux_lm));
}

// Radiant flux per ray and the lumens in the header alone: the rays carry the header's
// lumens. Without lumens anywhere the scene must give flux_lm; flux_lm rescales.
TEST(RayFile, ARadiantFileTakesItsHeadersLumens) {
    const Scene disk = ray_file_scene("disk.tm25ray", "normal = [0.0, 0.0, -1.0]");
    EXPECT_EQ(disk.source.flux_lm, 100.0); // the header's, not the rays' 0.2 W
    EXPECT_TRUE(disk.source.ray_file.index->layout.flux_radiant);
    EXPECT_EQ(disk.trace.rays, 200000u) << "every ray of the file, where [trace] sets none";
    EXPECT_EQ(ray_file_scene("disk.tm25ray", "flux_lm = 250.0").source.flux_lm, 250.0);
    try {
        (void)ray_file_scene("radiant_only.tm25ray", "");
        FAIL() << "a radiant-only file without flux_lm was read";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("flux_lm"), std::string::npos) << e.what();
    }
    EXPECT_EQ(ray_file_scene("radiant_only.tm25ray", "flux_lm = 5.0").source.flux_lm, 5.0);
}

// Written back (scene_to_toml) and read again: the same scene; its rays now counted by
// [trace] rays (the subsample's share), its frame and flux as read.
TEST(RayFile, ARayFileSceneRoundTrips) {
    const Scene s = ray_file_scene(
        "part.csv", "normal = [0.0, 0.6, -0.8]\nx_axis = [1.0, 0.0, 0.0]\nsubsample = 0.5");
    EXPECT_EQ(s.trace.rays, 1500u);
    const Scene again = parse_scene(scene_to_toml(s), s.path);
    EXPECT_TRUE(again == s);
    EXPECT_EQ(again.source.resolved_path, ray_files()("part.csv"));
    EXPECT_EQ(again.trace.rays, 1500u);
    EXPECT_EQ(again.source.axis, s.source.axis);
}

// A file cut short after the scene was read: tracing it fails with the file and the byte
// (not a crash in the reference tracer's threads).
TEST(RayFile, AFileCutAfterTheSceneWasReadFailsTheTraceNamingTheByte) {
    const std::string copy = ray_files()("cut.tm25ray");
    std::filesystem::copy_file(ray_files()("part.tm25ray"), copy,
                               std::filesystem::copy_options::overwrite_existing);
    const Scene s = ray_file_scene("cut.tm25ray", "normal = [0.0, 0.0, -1.0]");
    std::filesystem::resize_file(copy, std::filesystem::file_size(copy) / 2);
    try {
        (void)trace_reference(s.source, Surface::make(s.reflector, s.holder),
                              {.rays = s.trace.rays, .seed = 1, .threads = 2});
        FAIL() << "a cut file traced";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()).rfind(copy + ": byte ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("short file"), std::string::npos) << e.what();
    }
}

// Published files' quirks, both in one file: the spectral table's padding left out, and
// the header's luminous flux a NaN written big-endian (so unknown: the rays' own lumens).
TEST(RayFile, AMissingPaddingAndAByteSwappedNanAreRead) {
    const std::string path = ray_files()("weighted.tm25ray");
    std::ifstream in(path, std::ios::binary);
    const Tm25Header h = read_tm25_header(in, std::filesystem::file_size(path), path);
    EXPECT_TRUE(h.padding_missing);
    EXPECT_TRUE(h.flux_nan_swapped);
    EXPECT_EQ(h.ray_offset, ray_files().manifest["weighted"]["ray_offset"].get<std::uint64_t>());
    EXPECT_EQ(h.text[0], "FIRD test disk");
    const auto index = index_ray_file(path);
    EXPECT_EQ(index->layout.rays, 20000u);
    // Sums of 1 and 3, exact in double.
    EXPECT_EQ(index->file_flux_lm, ray_files().manifest["weighted"]["flux_lm"].get<double>());
}

// Each fault at the byte (CSV: the line) where the writer put it, and the file named.
TEST(RayFile, RefusalsNameTheFileAndTheByte) {
    const auto& m = ray_files().manifest;
    const std::vector<std::tuple<std::string, std::string, std::string>> cases = {
        {"short.tm25ray", fmt::format("byte {}", m["short"]["byte"].get<int>()), "short file"},
        {"bad_tag.tm25ray", "byte 0", "not 'TM25'"},
        {"size_mismatch.tm25ray", fmt::format("byte {}", m["size_mismatch"]["byte"].get<int>()),
         "disagrees with the file's size"},
        {"nan_direction.tm25ray", fmt::format("byte {}", m["nan_direction"]["byte"].get<int>()),
         "direction"},
        {"negative_flux.tm25ray", fmt::format("byte {}", m["negative_flux"]["byte"].get<int>()),
         "negative flux"},
        {"zero_direction.npy", fmt::format("byte {}", m["zero_direction"]["byte"].get<int>()),
         "direction (0, 0, 0)"},
        {"nan_direction.csv", fmt::format("line {}", m["nan_direction_csv"]["line"].get<int>()),
         "dx 'nan' is not a finite number"},
    };
    for (const auto& [name, where, what] : cases) {
        SCOPED_TRACE(name);
        const std::string path = ray_files()(name);
        try {
            (void)index_ray_file(path);
            ADD_FAILURE() << "read";
        } catch (const std::runtime_error& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(path + ": " + where + ":", 0), 0u) << message;
            EXPECT_NE(message.find(what), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        }
    }
}

// Unequal weights (1 lm and 3 lm): resampled to as many emissions as rays, the heavy rays'
// share of the emissions is their share of the flux. Each emission picks its ray by its
// own uniform, so the heavy count is at most binomial (stratification only lowers its
// variance): 4.5 sigma. And the emissions do not depend on how they are batched.
TEST(RayFile, ResamplingIsUnbiasedAndIndependentOfBatching) {
    const Scene s = ray_file_scene("weighted.tm25ray", "");
    const auto& w = ray_files().manifest["weighted"];
    std::ifstream heavy_in(ray_files()("weighted_heavy.txt"));
    std::string heavy_flags;
    heavy_in >> heavy_flags;
    // The placement is the identity (centre 0, normal +z, x axis +x): a ray's origin
    // names it.
    std::map<std::pair<double, double>, bool> heavy;
    const std::vector<RayRecord> file = read_all(*s.source.ray_file.index);
    for (std::size_t i = 0; i < file.size(); ++i)
        heavy[{file[i].position_mm.x, file[i].position_mm.y}] = heavy_flags[i] == '1';
    const std::uint64_t rays = s.trace.rays;
    ASSERT_EQ(rays, 20000u);
    std::vector<Ray> all;
    emit_ray_file_rays(s.source, 7, 0, rays, rays, [&](const Ray& r) { all.push_back(r); });
    ASSERT_EQ(all.size(), rays);
    double heavy_count = 0.0;
    for (const Ray& r : all) {
        const auto it = heavy.find({r.origin.x, r.origin.y});
        ASSERT_NE(it, heavy.end()) << "an emitted ray that is not in the file";
        heavy_count += it->second ? 1.0 : 0.0;
    }
    const double p = w["heavy_weight"].get<double>() / w["flux_lm"].get<double>();
    EXPECT_NEAR(heavy_count, p * double(rays), 4.5 * std::sqrt(double(rays) * p * (1 - p)));
    // Batches of 777 and 4096 + 1 (a checkpoint's stride): the same rays, bit for bit.
    for (const std::uint64_t batch : {std::uint64_t(777), kRayFileStride + 1}) {
        std::vector<Ray> batched;
        for (std::uint64_t first = 0; first < rays; first += batch)
            emit_ray_file_rays(s.source, 7, first, std::min(batch, rays - first), rays,
                               [&](const Ray& r) { batched.push_back(r); });
        ASSERT_EQ(batched.size(), all.size());
        for (std::size_t i = 0; i < all.size(); ++i) {
            ASSERT_EQ(batched[i].origin, all[i].origin) << "emission " << i;
            ASSERT_EQ(batched[i].direction, all[i].direction) << "emission " << i;
        }
    }
}

// subsample keeps that share of the file's rays, each at most once (equal weights: each
// emission picks one ray of its own run of 1 / subsample rays), and the source's flux;
// [trace] rays beside it is refused.
TEST(RayFile, SubsampleKeepsItsShareOfTheRaysAndTheFlux) {
    const Scene s = ray_file_scene("part.tm25ray", "subsample = 0.25");
    EXPECT_EQ(s.trace.rays, 750u);
    EXPECT_NEAR(s.source.flux_lm, ray_files().manifest["part"]["flux_lm"].get<double>(), 1e-9);
    std::set<std::tuple<double, double, double>> seen;
    emit_ray_file_rays(s.source, 3, 0, s.trace.rays, s.trace.rays, [&](const Ray& r) {
        seen.insert({r.origin.x, r.origin.y, r.direction.z});
    });
    EXPECT_EQ(seen.size(), 750u) << "a ray emitted twice";
    try {
        (void)ray_file_scene("part.tm25ray", "subsample = 0.25", "rays = 100");
        FAIL() << "rays and subsample both read";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("[trace] rays"), std::string::npos) << e.what();
    }
    try {
        (void)ray_file_scene("part.tm25ray", "subsample = 1.5");
        FAIL() << "a subsample above 1 read";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("subsample: must be > 0 and <= 1"), std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace fird::test
