// Calibration results as JSON, CSV, Markdown (the paper's Table 1 layout) and pictures
// (Table 1 on log-log axes; each semivariogram with its fitted model, as Figure 8).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "calibrate/calibration.hpp"
#include "plot/chart.hpp"

namespace fird {

// The charts of the pictures (the workbench draws them live).
plot::Chart rays_table_chart(const RaysTable& table, const std::string& scene_name);
plot::Chart semivariogram_chart(const ParameterSemivariogram& p, std::uint64_t rays,
                                const std::string& scene, FarFieldMetric metric);

nlohmann::json rays_table_json(const RaysTable& table);
std::string rays_table_markdown(const RaysTable& table, const std::string& scene_name);
// table1.csv, table1.md, table1.png and calibration.json in the directory.
void write_rays_table(const std::string& directory, const RaysTable& table,
                      const std::string& scene_name);

nlohmann::json semivariogram_json(const SemivariogramResult& result);
// series.csv, semivariogram.csv, resolution.csv (the resolvable step's probes),
// semivariogram_NAME.png and calibration.json.
void write_semivariograms(const std::string& directory, const SemivariogramResult& result,
                          const std::string& scene_name);

} // namespace fird
