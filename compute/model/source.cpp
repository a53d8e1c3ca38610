#include "source.hpp"

#include <algorithm>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include <glm/geometric.hpp>

#include "sampling/philox.hpp"
#include "sampling/sobol.hpp"
#include "sampling/strata.hpp"

namespace fird {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// The Philox stream that picks the rays sample_effective_rays shows (the rays use stream 0).
constexpr std::uint32_t kSampleStream = 1;

// Two unit vectors completing n to a right-handed orthonormal frame
// (Duff et al., "Building an orthonormal basis, revisited", 2017).
void frame(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
}

// Lambertian (cosine-weighted) direction about unit normal n.
glm::dvec3 cosine_direction(const glm::dvec3& n, double u1, double u2) {
    const double r = std::sqrt(u1);
    const double phi = kTwoPi * u2;
    const double cos_theta = std::sqrt(std::max(0.0, 1.0 - u1));
    glm::dvec3 t, b;
    frame(n, t, b);
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + cos_theta * n);
}

glm::dvec3 uniform_sphere(double u1, double u2) {
    const double z = 1.0 - 2.0 * u1;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = kTwoPi * u2;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

} // namespace

Ray sample_source(const SourceDesc& s, const std::array<double, 4>& u) {
    switch (s.kind) {
    case SourceKind::Cylinder: {
        const glm::dvec3 axis = glm::normalize(s.axis);
        glm::dvec3 t, b;
        frame(axis, t, b);
        const double along = (u[0] - 0.5) * s.length_mm;
        const double phi = kTwoPi * u[1];
        const glm::dvec3 normal = std::cos(phi) * t + std::sin(phi) * b;
        return {s.center_mm + along * axis + s.radius_mm * normal,
                cosine_direction(normal, u[2], u[3])};
    }
    case SourceKind::Sphere: {
        // Direction first: the joint density of the surface normal n (uniform) and the
        // direction d (Lambertian about n) is max(0, n.d) / (4 pi^2), symmetric in n and d;
        // so d uniform and n Lambertian about d is the same distribution, and the
        // direction now comes from the stratified uniforms (sampling/strata.hpp).
        const glm::dvec3 direction = uniform_sphere(u[0], u[1]);
        const glm::dvec3 normal = cosine_direction(direction, u[2], u[3]);
        return {s.center_mm + s.radius_mm * normal, direction};
    }
    case SourceKind::Point:
        if (s.emittance == Emittance::Cosine)
            return {s.center_mm, cosine_direction(glm::normalize(s.axis), u[0], u[1])};
        return {s.center_mm, uniform_sphere(u[0], u[1])};
    }
    return {s.center_mm, {0.0, 0.0, 1.0}};
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
