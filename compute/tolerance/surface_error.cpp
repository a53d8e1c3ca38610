#include "surface_error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "model/surface.hpp"
#include "sampling/philox.hpp"

namespace fird {

namespace {
constexpr int kFeatures = 64;
constexpr std::uint32_t kSurfaceStream = 20100;
constexpr int kMaxVertices = 801; // per side of the mesh
} // namespace

double SurfaceError::at(double x, double y) const {
    double z = 0.0;
    for (std::size_t m = 0; m < k_per_mm.size(); ++m)
        z += std::cos(k_per_mm[m].x * x + k_per_mm[m].y * y + phase_rad[m]);
    return k_per_mm.empty() ? 0.0 : rms_mm * std::sqrt(2.0 / double(k_per_mm.size())) * z;
}

SurfaceError draw_surface_error(double rms_mm, double correlation_mm, std::uint64_t seed,
                                std::uint64_t realisation) {
    SurfaceError e{.rms_mm = rms_mm};
    if (!(rms_mm > 0.0)) return e;
    for (int m = 0; m < kFeatures; ++m) {
        // Two normals for k, one uniform for the phase.
        const auto u = philox_uniforms(seed, realisation, kSurfaceStream + std::uint32_t(m));
        const auto [kx, ky] = standard_normals(u[0], u[1]);
        e.k_per_mm.push_back(glm::dvec2(kx, ky) / correlation_mm);
        e.phase_rad.push_back(2.0 * std::numbers::pi * u[2]);
    }
    return e;
}

PerturbedMesh perturbed_mesh(const Scene& scene, const SurfaceError& error, double correlation_mm,
                             const std::string& path) {
    const Surface surface = Surface::make(scene.reflector, scene.holder);
    const Holder& h = scene.holder;
    const glm::dvec3 size = h.max_mm - h.min_mm;
    const double spacing = std::min(correlation_mm / 4.0, std::min(size.x, size.y) / 200.0);
    const int nx = std::clamp(int(std::ceil(size.x / spacing)) + 1, 2, kMaxVertices);
    const int ny = std::clamp(int(std::ceil(size.y / spacing)) + 1, 2, kMaxVertices);
    // Too fine an error for the mesh, or for the height field the fast path traces it on,
    // would be traced smoothed away: refused, naming what resolves it.
    const double mesh_mm = std::max(size.x / (nx - 1), size.y / (ny - 1));
    const double texel_mm =
        std::max(size.x / scene.trace.heightfield_w, size.y / scene.trace.heightfield_h);
    if (mesh_mm > correlation_mm / 4.0 * (1.0 + 1e-9) || texel_mm > correlation_mm / 4.0)
        throw std::invalid_argument(fmt::format(
            "surface correlation length {} mm: below what this holder's mesh ({} vertices a "
            "side at most) and height field ({:.4g} mm texels) resolve at 4 points per length: "
            "use at least {:.4g} mm, or a finer [trace] heightfield",
            correlation_mm, kMaxVertices, texel_mm,
            4.0 * std::max(std::max(size.x, size.y) / (kMaxVertices - 1), texel_mm)));
    std::string obj = fmt::format("# fird tolerance: the reflector with a random surface error "
                                  "({:.4g} mm RMS)\n",
                                  error.rms_mm);
    double sum2 = 0.0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const double x = h.min_mm.x + size.x * i / (nx - 1);
            const double y = h.min_mm.y + size.y * j / (ny - 1);
            const double base = surface.height(x, y);
            const double z = std::clamp(base + error.at(x, y), h.min_mm.z, h.max_mm.z);
            sum2 += (z - base) * (z - base); // the error as traced: after the clamp
            obj += fmt::format("v {:.9g} {:.9g} {:.9g}\n", x, y, z);
        }
    for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
            const int a = j * nx + i + 1, b = a + 1, c = a + nx, d = c + 1; // OBJ counts from 1
            obj += fmt::format("f {} {} {}\nf {} {} {}\n", a, b, d, a, d, c);
        }
    write_text_file(path, obj);
    PerturbedMesh out;
    out.reflector = scene.reflector;
    out.reflector.family = Family::Mesh;
    out.reflector.parameters.clear();
    out.reflector.optimize.clear();
    out.reflector.mesh = MeshDesc{.file = path, .resolved_path = path, .unit_mm = 1.0};
    out.rms_mm = std::sqrt(sum2 / double(nx * ny));
    return out;
}

} // namespace fird
