// fird export: one lighting evaluation on the fast path, written as VTK XML files that
// open in ParaView as they are (scene.pvd opens them all), and a search's reflectors as
// a time series.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "model/source.hpp"
#include "optimize/search_types.hpp"
#include "vk/context.hpp"

namespace fird {

struct ExportOptions {
    std::map<std::string, double> parameters; // reflector overrides
    std::uint64_t rays = 0;                   // 0: the scene's
    std::uint32_t paths = 1000;               // sample ray paths
    std::uint32_t levels = 0; // coarsest quadtree levels written (0: as many as stay under
                              // kDefaultQuadtreeBoxes boxes)
};

// The quadtree boxes written by default, and the most any request may write (a box is
// 8 points and a cell: ~120 bytes before compression).
inline constexpr std::uint64_t kDefaultQuadtreeBoxes = 1'000'000;
inline constexpr std::uint64_t kMaxQuadtreeBoxes = 4'000'000;
inline constexpr std::uint32_t kMaxPaths = 1'000'000;

struct ExportedFile {
    std::string name;
    std::uint64_t bytes = 0;
};

struct ExportReport {
    std::vector<ExportedFile> files;
    RayTally tally; // the traced run's
    double energy_per_ray_lm = 0.0;
    std::vector<std::string> notes; // clamped requests, said once each
    std::uint32_t quadtree_levels = 0;
};

// Throws std::invalid_argument for a bad override (a parameter the family lacks, a
// value that makes no surface or cuts the source) or a request past the limits.
ExportReport export_scene(const vk::Context& ctx, const Scene& scene, const ExportOptions& options,
                          const std::string& directory);

// reflectors.pvd: the best reflector each time it improves (within each stage), as
// reflectors/best_NNNNNN.vts (the exact surface on a grid of at most 400 x 400), the
// time step its evaluation index: Figure 13 as an animation.
ExportReport export_search_reflectors(const Scene& scene, const SearchResult& result,
                                      const std::string& directory);

} // namespace fird
