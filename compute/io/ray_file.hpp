// Measured ray files as a light source's rays: IES TM-25 (io/tm25_file.hpp), .npy arrays
// of shape (N, 6) or (N, 7) and CSV files (io/ray_csv.hpp), each row x, y, z, dx, dy, dz
// [, flux] in the file's own frame, in mm. Read a record at a time from any record on,
// through a small buffer, so a file of any size is streamed, never held whole.
#pragma once

#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "io/ray_csv.hpp"

namespace fird {

enum class RayFileFormat { Tm25, Npy, Csv };

struct RayFileLayout {
    RayFileFormat format = RayFileFormat::Tm25;
    std::string path;
    std::uint64_t rays = 0;        // records (CSV: 0 until a reader has counted them)
    std::uint64_t data_offset = 0; // the byte at which record 0 begins (CSV: its line)
    std::uint32_t columns = 0;     // values per record (TM-25, npy)
    bool float64 = false;          // npy: float64 values (else float32)
    int flux_column = -1;          // each ray's flux, or -1: all rays carry the same
    bool flux_radiant = false;     // that flux is radiant (W), to be scaled to lumens
    // The file's luminous flux where its header gives it (TM-25); NaN otherwise.
    double header_flux_lm = std::numeric_limits<double>::quiet_NaN();
    CsvRayColumns csv;
    std::uint64_t csv_first_line = 2; // the line of record 0 (after the header line)
};

// The layout of the file at `path`, by its extension (.tm25ray, .ray: TM-25; .npy; .csv;
// any case). Throws std::runtime_error "PATH: byte N: what" (CSV: "line N").
RayFileLayout ray_file_layout(const std::string& path);

// One ray as read: the direction as the file gives it (not made unit: the placement into
// the scene does that, model/ray_file_source.hpp); flux in the file's unit (1 where there
// is none).
struct RayRecord {
    glm::dvec3 position_mm{0.0};
    glm::dvec3 direction{0.0, 0.0, 1.0};
    double flux = 1.0;
};

// Where a record begins: its byte and (CSV) its line.
struct RecordPosition {
    std::uint64_t byte = 0;
    std::uint64_t line = 0;
};

// Reads records in order from any record on. Each is checked: a non-finite position, a
// non-finite or zero direction and a negative or non-finite flux are refused with
// std::runtime_error naming the file and the byte (CSV: the line).
class RayFileReader {
  public:
    explicit RayFileReader(const RayFileLayout& layout);
    // Moves to record `index`, which begins at `at` (used by CSV files, whose records are
    // not of one size; the fixed-size formats compute it).
    void seek(std::uint64_t index, const RecordPosition& at = {});
    // The next record; false past the last.
    bool next(RayRecord& ray);
    // Up to `max` next records into `out`; how many (fewer only past the last).
    std::size_t read(RayRecord* out, std::size_t max);
    std::uint64_t index() const { return index_; }
    RecordPosition position() const;

  private:
    bool next_fixed(RayRecord& ray);
    bool next_csv(RayRecord& ray);
    [[noreturn]] void refuse(std::uint64_t column, const std::string& what) const;
    void check(RayRecord& ray) const;

    const RayFileLayout* layout_;
    std::ifstream in_;
    std::uint64_t index_ = 0;
    // The fixed-size formats: a chunk of records, and the index of its first.
    std::vector<char> chunk_;
    std::uint64_t chunk_first_ = 0;
    std::uint64_t chunk_records_ = 0;
    // CSV: where the next line begins, and its number.
    RecordPosition csv_at_;
    std::string line_;
};

} // namespace fird
