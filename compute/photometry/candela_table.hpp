// One in-memory candela table for IES LM-63 and EULUMDAT files: type C angles over the
// full C range (the file's symmetry expanded), candela with the file's multipliers
// applied, and its metadata. The intensity between the stored angles is linear in C and
// linear in cos(gamma): flux integration and far-field conversion share that model, so
// a far field made from a table holds exactly the table's flux.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fird {

enum class PhotometricType { A, B, C };
enum class Symmetry { None, Rotational, C0C180, C90C270, Quadrant };

const char* to_string(PhotometricType type);
const char* to_string(Symmetry symmetry);

struct CandelaTable {
    std::string path;
    std::string format;                             // "ies" or "ldt"
    std::string version;                            // "LM-63-1986", ..., "LM-63-2019", "EULUMDAT"
    PhotometricType file_type = PhotometricType::C; // as stored (A and B are resampled to C)
    Symmetry symmetry = Symmetry::None;             // as stored
    std::size_t n_vertical = 0;                     // angles as stored in the file
    std::size_t n_horizontal = 0;
    std::optional<double> flux_declared_lm; // IES: lamps x lumens; LDT: lamp flux x LORL
    bool absolute = false;                  // IES lumens = -1, LDT negative lamp count
    std::vector<std::pair<std::string, std::string>> keywords; // IES keywords, LDT fields

    // Type C: c_deg increasing in [0, 360) and wrapping (one plane: rotational symmetry);
    // gamma_deg increasing in [0, 180] (0 = nadir); cd[c * gamma_deg.size() + g].
    std::vector<double> c_deg;
    std::vector<double> gamma_deg;
    std::vector<double> cd;

    double at(std::size_t c, std::size_t g) const { return cd[c * gamma_deg.size() + g]; }
    double peak_cd() const;
};

// The interpolated intensity (cd) in the direction (C, gamma), degrees; zero outside
// the stored gamma range.
double intensity_cd(const CandelaTable& table, double c_deg, double gamma_deg);

// Total flux, the exact integral of the interpolated intensity over the sphere (the
// zonal trapezoid rule in cos(gamma) and C).
double integrated_flux_lm(const CandelaTable& table);

// Sets table.c_deg and table.cd from the planes a file stores for `symmetry` (angles as
// in the file: 0..90, 0..180, 90..270, 0..360, or one plane), mirroring them over the
// full C range. plane_cd[p] holds table.gamma_deg.size() values.
void expand_symmetry(CandelaTable& table, const std::vector<double>& stored_c_deg,
                     const std::vector<std::vector<double>>& plane_cd);

// Resamples a type A or B distribution onto a type C grid (C every 1 deg, gamma every
// 0.5 deg). sample(h_deg, v_deg) is the file's interpolated intensity, zero outside its
// range. Type B: planes share the luminaire's lateral axis (y); (H, V) = (0, 0) is nadir,
// (0, 90) is +x (photometric horizontal): d = (cos H sin V, sin H, -cos H cos V).
// Type A: planes share the vertical axis; (0, 0) is +x, V = -90 is nadir:
// d = (cos V cos H, -cos V sin H, sin V). Both with nadir -z, as type C's
// d = (sin g cos C, sin g sin C, -cos g).
void resample_to_type_c(CandelaTable& table, PhotometricType type,
                        const std::function<double(double h_deg, double v_deg)>& sample);

} // namespace fird
