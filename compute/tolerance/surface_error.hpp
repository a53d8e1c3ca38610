// A smooth random surface error (fird tolerance): a stationary Gaussian field of given RMS
// and correlation length, as a sum of random Fourier features (Rahimi and Recht, 2007):
// z(p) = rms sqrt(2/M) sum_m cos(k_m . p + phi_m), k_m ~ N(0, 1/L^2) per axis, phi_m
// uniform, whose covariance is rms^2 exp(-|d|^2 / (2 L^2)) over the draws. Reproducible
// from (seed, realisation) with the counter-based generator.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "model/scene.hpp"

namespace fird {

struct SurfaceError {
    double rms_mm = 0.0;
    std::vector<glm::dvec2> k_per_mm;
    std::vector<double> phase_rad;
    double at(double x_mm, double y_mm) const;
};

SurfaceError draw_surface_error(double rms_mm, double correlation_mm, std::uint64_t seed,
                                std::uint64_t realisation);

struct PerturbedMesh {
    ReflectorDesc reflector; // family mesh, reading `path`
    double rms_mm = 0.0;     // the error's RMS over the mesh's vertices
};

// The scene's reflector (clamped to the holder) plus the error, sampled on a vertex grid
// over the holder's footprint fine enough for the error (4 vertices per correlation
// length, and at least 200 across), clamped again, written to `path` as an OBJ height
// field that both tracers read as the mesh family (the material kept).
PerturbedMesh perturbed_mesh(const Scene& scene, const SurfaceError& error, double correlation_mm,
                             const std::string& path);

} // namespace fird
