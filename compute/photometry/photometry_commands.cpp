#include "photometry_commands.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>

#include "io/npy.hpp"
#include "photometry/farfield_photometry.hpp"
#include "photometry/photometry_file.hpp"
#include "photometry/polar_plot.hpp"

namespace fird {

namespace {
std::string extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}
} // namespace

nlohmann::json photometry_info_json(const CandelaTable& t) {
    nlohmann::json j = {{"format", t.format},
                        {"version", t.version},
                        {"photometric_type", to_string(t.file_type)},
                        {"symmetry", to_string(t.symmetry)},
                        {"n_vertical", t.n_vertical},
                        {"n_horizontal", t.n_horizontal},
                        {"absolute", t.absolute},
                        {"flux_integrated_lm", integrated_flux_lm(t)},
                        {"peak_cd", t.peak_cd()}};
    j["flux_declared_lm"] = t.flux_declared_lm ? nlohmann::json(*t.flux_declared_lm) : nullptr;
    return j;
}

void convert_photometry(const std::string& in, const std::string& out, const ConvertOptions& o) {
    CandelaTable table;
    if (extension(in) == ".npy") {
        const NpyArray a = read_npy_f32(in);
        if (a.shape.size() != 2 || a.shape[0] == 0 || a.shape[1] == 0 || a.shape[0] > 1u << 20 ||
            a.shape[1] > 1u << 20)
            throw std::invalid_argument(in + ": a far field is a 2-D array (rows, columns)");
        const FarField ff{std::uint32_t(a.shape[1]), std::uint32_t(a.shape[0]),
                          std::vector<double>(a.values.begin(), a.values.end())};
        table = table_from_farfield(ff, o.c_step_deg, o.gamma_step_deg);
    } else {
        table = read_photometry(in);
    }
    const std::string ext = extension(out);
    if (ext == ".npy") {
        const FarField ff = farfield_from_table(table, o.farfield_w, o.farfield_h);
        write_npy_f32(out, ff.lm, ff.height, ff.width);
    } else if (ext == ".png") {
        write_polar_plot_png(out, table);
    } else if (ext == ".ies" || ext == ".ldt") {
        PhotometryLabels labels;
        labels.test =
            fmt::format("converted by FIRD from {}", std::filesystem::path(in).filename().string());
        for (const auto& [key, value] : table.keywords)
            if (key == "LUMINAIRE" || key == "luminaire name") labels.luminaire = value;
        write_photometry(out, table, labels);
    } else {
        throw std::invalid_argument(out + ": unknown output type (.ies, .ldt, .npy or .png)");
    }
}

} // namespace fird
