#include "ray_file.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "io/npy.hpp"
#include "io/tm25_file.hpp"

namespace fird {

namespace {

// Records read per chunk of a fixed-size file: with TM-25's largest usual record (7
// floats) 112 KiB, whatever the file's size.
constexpr std::uint64_t kChunkRecords = 4096;

std::string lowercase_extension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return e;
}

} // namespace

RayFileLayout ray_file_layout(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot open the ray file", path));
    std::error_code ec;
    const std::uint64_t bytes = std::filesystem::file_size(path, ec);
    if (ec) throw std::runtime_error(fmt::format("{}: cannot read its size", path));
    RayFileLayout l;
    l.path = path;
    const std::string ext = lowercase_extension(path);
    if (ext == ".tm25ray" || ext == ".ray") {
        const Tm25Header h = read_tm25_header(in, bytes, path);
        l.format = RayFileFormat::Tm25;
        l.rays = h.rays;
        l.data_offset = h.ray_offset;
        l.columns = h.columns;
        // Luminous flux per ray where the file has it; else radiant, scaled to the
        // header's lumens.
        l.flux_column = h.luminous_column >= 0 ? h.luminous_column : h.radiant_column;
        l.flux_radiant = h.luminous_column < 0 && h.radiant_column >= 0;
        l.header_flux_lm = h.luminous_flux_lm;
    } else if (ext == ".npy") {
        const NpyHeader h = read_npy_header(in, path);
        if (h.shape.size() != 2 || (h.shape[1] != 6 && h.shape[1] != 7))
            throw std::runtime_error(fmt::format(
                "{}: byte 10: an array of shape (N, 6) or (N, 7) is read (x, y, z, dx, dy, "
                "dz[, flux])",
                path));
        l.format = RayFileFormat::Npy;
        l.rays = h.shape[0];
        l.data_offset = h.data_offset;
        l.columns = std::uint32_t(h.shape[1]);
        l.float64 = h.float64;
        l.flux_column = h.shape[1] == 7 ? 6 : -1;
        const std::uint64_t need = l.data_offset + l.rays * l.columns * (l.float64 ? 8 : 4);
        if (need != bytes)
            throw std::runtime_error(fmt::format(
                "{}: byte {}: the header's {} rays need {} bytes from here, the file has {}", path,
                l.data_offset, l.rays, need - l.data_offset,
                bytes > l.data_offset ? bytes - l.data_offset : 0));
    } else if (ext == ".csv") {
        std::string header;
        if (!std::getline(in, header))
            throw std::runtime_error(fmt::format("{}: line 1: no header line", path));
        if (!header.empty() && header.back() == '\r') header.pop_back();
        l.format = RayFileFormat::Csv;
        l.csv = csv_ray_columns(header, path);
        l.data_offset = std::uint64_t(in.tellg());
        l.flux_column = l.csv.flux >= 0 ? 6 : -1;
    } else {
        throw std::runtime_error(fmt::format(
            "{}: a ray file is read by its extension: .tm25ray (or .ray), .npy or .csv", path));
    }
    return l;
}

RayFileReader::RayFileReader(const RayFileLayout& layout)
    : layout_(&layout), in_(layout.path, std::ios::binary) {
    if (!in_) throw std::runtime_error(fmt::format("{}: cannot open the ray file", layout.path));
    seek(0, {layout.data_offset, layout.csv_first_line});
}

void RayFileReader::seek(std::uint64_t index, const RecordPosition& at) {
    index_ = index;
    if (layout_->format == RayFileFormat::Csv) {
        csv_at_ = at;
        in_.clear();
        in_.seekg(std::streamoff(at.byte));
    }
    chunk_records_ = 0;
}

RecordPosition RayFileReader::position() const {
    if (layout_->format == RayFileFormat::Csv) return csv_at_;
    const std::uint64_t bytes = layout_->columns * (layout_->float64 ? 8u : 4u);
    return {layout_->data_offset + index_ * bytes, 0};
}

void RayFileReader::refuse(std::uint64_t column, const std::string& what) const {
    if (layout_->format == RayFileFormat::Csv)
        throw std::runtime_error(
            fmt::format("{}: line {}: ray {}: {}", layout_->path, csv_at_.line, index_, what));
    const std::uint64_t size = layout_->float64 ? 8u : 4u;
    throw std::runtime_error(fmt::format("{}: byte {}: ray {}: {}", layout_->path,
                                         position().byte + column * size, index_, what));
}

void RayFileReader::check(RayRecord& r) const {
    const glm::dvec3 p = r.position_mm, d = r.direction;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        refuse(0, fmt::format("position ({}, {}, {}) is not finite", p.x, p.y, p.z));
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
        refuse(3, fmt::format("direction ({}, {}, {}) is not finite", d.x, d.y, d.z));
    if (!(glm::dot(d, d) > 0.0)) refuse(3, "direction (0, 0, 0): a ray needs a direction");
    const std::uint64_t flux_column = std::uint64_t(std::max(layout_->flux_column, 0));
    if (!std::isfinite(r.flux)) refuse(flux_column, fmt::format("flux {} is not finite", r.flux));
    if (r.flux < 0.0) refuse(flux_column, fmt::format("negative flux {}", r.flux));
}

bool RayFileReader::next(RayRecord& ray) {
    return layout_->format == RayFileFormat::Csv ? next_csv(ray) : next_fixed(ray);
}

bool RayFileReader::next_fixed(RayRecord& ray) {
    return read(&ray, 1) == 1;
}

std::size_t RayFileReader::read(RayRecord* out, std::size_t max) {
    const RayFileLayout& l = *layout_;
    std::size_t n = 0;
    if (l.format == RayFileFormat::Csv) {
        while (n < max && next_csv(out[n]))
            ++n;
        return n;
    }
    const std::uint64_t size = l.float64 ? 8u : 4u;
    const std::uint64_t bytes = l.columns * size;
    const int flux_column = l.flux_column;
    // Little-endian: copied as is on a little-endian host, byte by byte on another.
    const auto value = [&](const char* record, int column) -> double {
        const char* at = record + std::uint64_t(column) * size;
        if constexpr (std::endian::native == std::endian::little) {
            if (l.float64) {
                double d = 0.0;
                std::memcpy(&d, at, 8);
                return d;
            }
            float f = 0.0f;
            std::memcpy(&f, at, 4);
            return double(f);
        }
        std::uint64_t bits = 0;
        for (std::uint64_t k = size; k-- > 0;)
            bits = (bits << 8) | static_cast<unsigned char>(at[k]);
        return l.float64 ? std::bit_cast<double>(bits)
                         : double(std::bit_cast<float>(std::uint32_t(bits)));
    };
    while (n < max && index_ < l.rays) {
        if (index_ < chunk_first_ || index_ >= chunk_first_ + chunk_records_) {
            chunk_first_ = index_;
            chunk_records_ = std::min(kChunkRecords, l.rays - index_);
            chunk_.resize(std::size_t(chunk_records_ * bytes));
            in_.clear();
            in_.seekg(std::streamoff(l.data_offset + index_ * bytes));
            in_.read(chunk_.data(), std::streamsize(chunk_.size()));
            if (!in_)
                throw std::runtime_error(fmt::format("{}: byte {}: short file: cannot read ray {}",
                                                     l.path, l.data_offset + index_ * bytes,
                                                     index_));
        }
        const std::uint64_t here =
            std::min<std::uint64_t>(max - n, chunk_first_ + chunk_records_ - index_);
        const char* record = chunk_.data() + (index_ - chunk_first_) * bytes;
        for (std::uint64_t k = 0; k < here; ++k, record += bytes) {
            RayRecord& r = out[n + k];
            r.position_mm = {value(record, 0), value(record, 1), value(record, 2)};
            r.direction = {value(record, 3), value(record, 4), value(record, 5)};
            r.flux = flux_column >= 0 ? value(record, flux_column) : 1.0;
            // One test for the common case; check() finds and names the fault.
            const glm::dvec3 d = r.direction;
            const double sum =
                r.position_mm.x + r.position_mm.y + r.position_mm.z + d.x + d.y + d.z + r.flux;
            if (!std::isfinite(sum) || !(glm::dot(d, d) > 0.0) || r.flux < 0.0) {
                index_ += k;
                check(r);
                index_ -= k;
            }
        }
        index_ += here;
        n += here;
    }
    return n;
}

bool RayFileReader::next_csv(RayRecord& ray) {
    for (;;) {
        if (!std::getline(in_, line_)) return false;
        const RecordPosition here = csv_at_;
        csv_at_.byte += line_.size() + (in_.eof() ? 0 : 1);
        ++csv_at_.line;
        if (!line_.empty() && line_.back() == '\r') line_.pop_back();
        if (line_.find_first_not_of(" \t") == std::string::npos) continue; // a blank line
        const RecordPosition next = csv_at_;
        csv_at_ = here; // messages name this record's line
        const std::array<double, 7> v =
            parse_csv_ray(line_, layout_->csv, layout_->path, here.line);
        ray.position_mm = {v[0], v[1], v[2]};
        ray.direction = {v[3], v[4], v[5]};
        ray.flux = v[6];
        check(ray);
        csv_at_ = next;
        ++index_;
        return true;
    }
}

} // namespace fird
