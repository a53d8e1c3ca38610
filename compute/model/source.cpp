#include "source.hpp"

#include <algorithm>

#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include <glm/geometric.hpp>

#include "model/ray_file_source.hpp"
#include "sampling/philox.hpp"
#include "sampling/sobol.hpp"
#include "sampling/strata.hpp"

namespace fird {

namespace {

// The Philox stream that picks the rays sample_effective_rays shows (the rays use stream 0).
constexpr std::uint32_t kSampleStream = 1;

} // namespace

bool source_has_axis(const SourceDesc& s) {
    return s.kind != SourceKind::Sphere &&
           !(s.kind == SourceKind::Point && s.emittance == Emittance::Isotropic);
}

glm::dvec3 default_x_axis(const glm::dvec3& normal) {
    const glm::dvec3 n = glm::normalize(normal);
    const glm::dvec3 x =
        std::abs(n.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    return glm::normalize(x - glm::dot(x, n) * n);
}

gpu::emission::Emitter emitter_of(const SourceDesc& s, const glm::dvec3& origin) {
    gpu::emission::Emitter e{};
    switch (s.kind) {
    case SourceKind::Cylinder:
        e.kind = gpu::kSourceCylinder;
        break;
    case SourceKind::Sphere:
        e.kind = gpu::kSourceSphere;
        break;
    case SourceKind::Point:
        e.kind =
            s.emittance == Emittance::Cosine ? gpu::kSourcePointCosine : gpu::kSourcePointIsotropic;
        break;
    case SourceKind::Disk:
        e.kind = gpu::kSourceDisk;
        break;
    case SourceKind::Rectangle:
        e.kind = gpu::kSourceRectangle;
        break;
    case SourceKind::Photometric:
        e.kind = gpu::kSourcePhotometric;
        if (!s.table.floats)
            throw std::invalid_argument("a photometric source without its distribution");
        e.table_c = s.table.c_angles;
        e.table_g = s.table.gamma_angles;
        break;
    case SourceKind::RayFile:
        e.kind = gpu::kSourceRayFile; // its rays are read, not sampled (ray_file_source.hpp)
        break;
    }
    e.center = s.center_mm - origin;
    e.axis = glm::normalize(s.axis);
    // Perpendicular to the axis whatever the caller passed (the scene file refuses an
    // x_axis along the normal; a cylinder or a point has no use for one).
    const glm::dvec3 across = s.x_axis - glm::dot(s.x_axis, e.axis) * e.axis;
    e.x_axis = glm::length(across) > 1e-3 ? glm::normalize(across) : default_x_axis(e.axis);
    e.length_mm = s.length_mm;
    e.radius_mm = s.radius_mm;
    e.width_mm = s.width_mm;
    e.height_mm = s.height_mm;
    return e;
}

Ray sample_source(const SourceDesc& s, const std::array<double, 4>& u) {
    if (s.kind == SourceKind::RayFile)
        throw std::invalid_argument("a ray file's rays are read (emit_ray), not sampled");
    const gpu::emission::Emission m =
        gpu::emission::sample_emitter(emitter_of(s), glm::dvec4(u[0], u[1], u[2], u[3]),
                                      s.table.floats ? s.table.floats->data() : nullptr);
    return {m.origin, m.direction};
}

Ray emit_ray(const SourceDesc& source, SamplerKind sampler, std::uint64_t seed, std::uint64_t index,
             std::uint64_t rays) {
    if (source.kind != SourceKind::RayFile)
        return sample_source(source, ray_uniforms(sampler, seed, index, rays));
    Ray ray{};
    emit_ray_file_rays(source, seed, index, 1, rays, [&](const Ray& r) { ray = r; });
    return ray;
}

std::array<double, 4> ray_uniforms(SamplerKind sampler, std::uint64_t seed, std::uint64_t index,
                                   std::uint64_t rays) {
    if (index >= rays)
        throw std::invalid_argument(
            fmt::format("ray {} of {}: past the rays emitted", index, rays));
    if (sampler == SamplerKind::Sobol) return sobol_uniforms(seed, index);
    if (sampler == SamplerKind::Random) return philox_uniforms(seed, index, 0u);
    return stratified_uniforms(seed, index, rays);
}

bool clip_to_box(const Ray& ray, const glm::dvec3& lo, const glm::dvec3& hi, double& t_enter,
                 double& t_exit) {
    double t0 = 0.0;
    double t1 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        const double o = ray.origin[k];
        const double d = ray.direction[k];
        if (d == 0.0) {
            if (o < lo[k] || o > hi[k]) return false; // parallel and outside the slab
            continue;
        }
        double ta = (lo[k] - o) / d;
        double tb = (hi[k] - o) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    t_enter = t0;
    t_exit = t1;
    return true;
}

bool ray_meets_box(const Ray& ray, const Holder& holder) {
    double t0 = 0.0;
    double t1 = 0.0;
    return clip_to_box(ray, holder.min_mm, holder.max_mm, t0, t1);
}

std::vector<std::uint64_t> sample_effective_ray_indices(const Scene& s, std::uint32_t k) {
    // One index at random in each of m equal runs of the emission order, m growing until
    // k are found: the whole emission is covered (the stratified sampler emits in direction
    // order, so a prefix would hold the zenith's directions only), and not on a lattice
    // (evenly spaced indices pick a regular sublattice of its direction strata).
    std::vector<std::uint64_t> found;
    for (std::uint64_t m = 4ull * k + 1; found.size() < k; m *= 2) {
        m = std::min<std::uint64_t>(m, s.trace.rays);
        found.clear();
        for (std::uint64_t j = 0; j < m; ++j) {
            const double jitter = philox_uniforms(s.trace.seed, j, kSampleStream)[0];
            const auto i =
                std::min(s.trace.rays - 1,
                         std::uint64_t((double(j) + jitter) * double(s.trace.rays) / double(m)));
            const Ray r = emit_ray(s.source, s.trace.sampler, s.trace.seed, i, s.trace.rays);
            if (ray_meets_box(r, s.holder)) found.push_back(i);
        }
        if (m == s.trace.rays) break;
    }
    if (found.size() <= k) return found;
    std::vector<std::uint64_t> indices; // k of them, evenly over the emission order
    for (std::uint32_t j = 0; j < k; ++j)
        indices.push_back(found[std::size_t(std::uint64_t(j) * found.size() / k)]);
    return indices;
}

std::vector<Ray> sample_effective_rays(const Scene& s, std::uint32_t k) {
    std::vector<Ray> rays;
    for (const std::uint64_t i : sample_effective_ray_indices(s, k))
        rays.push_back(emit_ray(s.source, s.trace.sampler, s.trace.seed, i, s.trace.rays));
    return rays;
}

} // namespace fird
