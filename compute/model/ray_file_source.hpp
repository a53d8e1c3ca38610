// A measured ray file as the light source (DESIGN.md §2: its coordinates are its local
// frame, placed by center_mm, normal and x_axis): the index read once when the scene is
// read, and the rays it emits, streamed from the file as they are traced.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "io/ray_file.hpp"
#include "model/scene.hpp"
#include "model/source.hpp"

namespace fird {

// The index keeps a checkpoint every kRayFileStride records: 16 bytes each, so a 20-million
// ray file's index takes 80 KB, and a ray is found by reading at most this many records.
inline constexpr std::uint64_t kRayFileStride = 4096;

struct RayFileIndex {
    RayFileLayout layout;
    // The rays' weights in the file's unit (its flux per ray; 1 each where it has none).
    double weight_total = 0.0;
    // The file's luminous flux: its header's, else the sum of a luminous flux column; NaN
    // where the file gives none (a radiant-only TM-25 file without the header's lumens, an
    // .npy or CSV file without a flux column).
    double file_flux_lm = std::numeric_limits<double>::quiet_NaN();
    bool equal_weights = true;             // every ray carries the same flux
    std::vector<double> cumulative;        // weight of the records before record k * stride
    std::vector<RecordPosition> positions; // where record k * stride begins
    glm::dvec3 origin_min_mm{0.0};         // the rays' origins' bounding box, file frame
    glm::dvec3 origin_max_mm{0.0};
};

// Reads the file through once, in a buffer of bounded size: every record checked (the
// refusals of io/ray_file.hpp), the weights summed, the extent found.
std::shared_ptr<const RayFileIndex> index_ray_file(const std::string& path);

// Emissions first .. first + count - 1 of the `rays` a ray file source emits under `seed`,
// in order, placed in the scene. The file is resampled to `rays` rays of equal flux
// (flux_lm / rays each, as every source's far field counts them) by stratified
// resampling: emission e takes the ray whose share of the cumulative weight holds
// (e + u_e) W / rays, u_e uniform from Philox on (seed, e). Ray i is thereby emitted
// rays w_i / W times in expectation, exactly (unbiased), and the count is always `rays`.
// With `rays` equal to the file's rays and equal weights every ray is emitted once, in
// the file's order. u_e depends on (seed, e) alone: the rays do not depend on batching.
void emit_ray_file_rays(const SourceDesc& source, std::uint64_t seed, std::uint64_t first,
                        std::uint64_t count, std::uint64_t rays,
                        const std::function<void(const Ray&)>& emit);

// The scene's emission count where it sets none: the file's rays times `subsample`
// (0 < subsample <= 1), at least 1.
std::uint64_t subsampled_rays(const RayFileIndex& index, double subsample);

} // namespace fird
