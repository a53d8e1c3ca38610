#include "ray_file_source.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <glm/geometric.hpp>

#include "sampling/philox.hpp"

namespace fird {

namespace {
// The Philox stream of the resampling's uniforms (the analytic emitters' rays use stream
// 0, sample_effective_rays' picks stream 1).
constexpr std::uint32_t kResampleStream = 2;
} // namespace

std::shared_ptr<const RayFileIndex> index_ray_file(const std::string& path) {
    auto index = std::make_shared<RayFileIndex>();
    index->layout = ray_file_layout(path);
    RayFileReader reader(index->layout);
    // A checkpoint before each run of kRayFileStride records, read at once.
    std::vector<RayRecord> block(kRayFileStride);
    double total = 0.0;
    std::optional<double> first_flux;
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    for (;;) {
        index->cumulative.push_back(total);
        index->positions.push_back(reader.position());
        const std::size_t n = reader.read(block.data(), block.size());
        for (std::size_t k = 0; k < n; ++k) {
            const RayRecord& r = block[k];
            if (!first_flux) first_flux = r.flux;
            if (r.flux != *first_flux) index->equal_weights = false;
            total += r.flux;
            lo = glm::min(lo, r.position_mm);
            hi = glm::max(hi, r.position_mm);
        }
        if (n < block.size()) break;
    }
    RayFileLayout& l = index->layout;
    l.rays = reader.index();
    if (l.rays == 0) throw std::runtime_error(fmt::format("{}: no rays", path));
    if (!(total > 0.0)) throw std::runtime_error(fmt::format("{}: every ray's flux is 0", path));
    index->weight_total = total;
    index->origin_min_mm = lo;
    index->origin_max_mm = hi;
    if (std::isfinite(l.header_flux_lm))
        index->file_flux_lm = l.header_flux_lm;
    else if (l.flux_column >= 0 && !l.flux_radiant)
        index->file_flux_lm = total;
    return index;
}

std::uint64_t subsampled_rays(const RayFileIndex& index, double subsample) {
    return std::max<std::uint64_t>(
        1, std::uint64_t(std::llround(subsample * double(index.layout.rays))));
}

void emit_ray_file_rays(const SourceDesc& s, std::uint64_t seed, std::uint64_t first,
                        std::uint64_t count, std::uint64_t rays,
                        const std::function<void(const Ray&)>& emit) {
    if (!s.ray_file.index) throw std::invalid_argument("a ray file source without its index");
    if (count == 0) return;
    if (first + count > rays)
        throw std::invalid_argument(
            fmt::format("rays {} to {} of {}: past the rays emitted", first, first + count, rays));
    const RayFileIndex& index = *s.ray_file.index;
    const gpu::emission::Emitter e = emitter_of(s);
    const glm::dvec3 y_axis = glm::cross(e.axis, e.x_axis);
    const auto place = [&](const RayRecord& r) {
        const glm::dvec3 p = r.position_mm, d = r.direction;
        return Ray{e.center + p.x * e.x_axis + p.y * y_axis + p.z * e.axis,
                   glm::normalize(d.x * e.x_axis + d.y * y_axis + d.z * e.axis)};
    };
    // Equal weights and as many emissions as rays: emission e is ray e, whatever u_e
    // ((e + u_e) W / N lies in ray e's share), so the file is read straight through.
    if (index.equal_weights && rays == index.layout.rays) {
        const std::size_t k = std::size_t(first / kRayFileStride);
        RayFileReader reader(index.layout);
        reader.seek(std::uint64_t(k) * kRayFileStride, index.positions[k]);
        std::vector<RayRecord> block(std::size_t(std::min<std::uint64_t>(count, 1024)));
        for (RayRecord r; reader.index() < first && reader.next(r);) {
        }
        for (std::uint64_t done = 0; done < count;) {
            const std::size_t n = reader.read(
                block.data(), std::size_t(std::min<std::uint64_t>(block.size(), count - done)));
            if (n == 0) throw std::logic_error("a ray file index past the file's end");
            for (std::size_t j = 0; j < n; ++j)
                emit(place(block[j]));
            done += n;
        }
        return;
    }
    const double per_emission = index.weight_total / double(rays);
    const auto target = [&](std::uint64_t k) {
        return (double(k) + philox_uniforms(seed, k, kResampleStream)[0]) * per_emission;
    };
    // From the last checkpoint at or before the first target on, the records are read in
    // order: the targets grow with the emission index.
    const double t0 = target(first);
    const auto after = std::upper_bound(index.cumulative.begin(), index.cumulative.end(), t0);
    // (A target rounded up to the total would find the checkpoint past the last record,
    // where a file of a multiple of the stride has one: the one before it holds rays.)
    const std::size_t k =
        std::min(std::size_t(std::max<std::ptrdiff_t>(after - index.cumulative.begin() - 1, 0)),
                 std::size_t((index.layout.rays - 1) / kRayFileStride));
    RayFileReader reader(index.layout);
    reader.seek(std::uint64_t(k) * kRayFileStride, index.positions[k]);
    double before = index.cumulative[k]; // the weight of the records before `current`
    RayRecord current;
    if (!reader.next(current)) throw std::logic_error("a ray file index past the file's end");
    RayRecord last_weighted = current; // the last ray read with a weight (rounding at the end)
    for (std::uint64_t i = first; i < first + count; ++i) {
        const double t = i == first ? t0 : target(i);
        while (!(t < before + current.flux)) {
            if (current.flux > 0.0) last_weighted = current;
            before += current.flux;
            if (!reader.next(current)) {
                current = last_weighted; // t at the total, by rounding: the last ray
                before -= current.flux;
                break;
            }
        }
        emit(place(current));
    }
}

} // namespace fird
