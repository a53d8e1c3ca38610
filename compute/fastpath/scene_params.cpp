#include "scene_params.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <glm/trigonometric.hpp>

#include "model/source.hpp"
#include "model/source_clearance.hpp"
#include "model/surface.hpp"
#include "sampling/sobol.hpp"

namespace fird {

QuadtreeLayout quadtree_layout(std::uint32_t width, std::uint32_t height) {
    if (width == 0 || height == 0)
        throw std::invalid_argument("height field must be at least 1 x 1");
    QuadtreeLayout q;
    std::uint32_t w = width, h = height;
    std::uint64_t offset = 0;
    for (;;) {
        if (q.levels == FIRD_MAX_LEVELS)
            throw std::invalid_argument("height field too large for the quadtree");
        q.w[q.levels] = w;
        q.h[q.levels] = h;
        q.offset[q.levels] = std::uint32_t(offset);
        offset += std::uint64_t(w) * h;
        ++q.levels;
        if (w == 1 && h == 1) break;
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    q.total_floats = offset;
    return q;
}

glm::dvec3 frame_origin(const Holder& holder) {
    return 0.5 * (holder.min_mm + holder.max_mm);
}

gpu::SceneParams scene_params(const Scene& s, std::uint64_t seed) {
    gpu::SceneParams p{};
    const SourceBox box = source_box(s.source);
    const glm::dvec3 origin = frame_origin(s.holder);
    const gpu::emission::Emitter emitter = emitter_of(s.source, origin);
    double extent_mm = 0.0;
    for (int k = 0; k < 3; ++k) {
        p.holder_min[k] = float(s.holder.min_mm[k] - origin[k]);
        p.holder_max[k] = float(s.holder.max_mm[k] - origin[k]);
        p.source_center[k] = float(emitter.center[k]);
        p.source_axis[k] = float(emitter.axis[k]);
        p.source_x_axis[k] = float(emitter.x_axis[k]);
        p.source_box_min[k] = float(box.lo[k] - origin[k]);
        p.source_box_max[k] = float(box.hi[k] - origin[k]);
        extent_mm = std::max(extent_mm, 0.5 * (s.holder.max_mm[k] - s.holder.min_mm[k]));
    }
    // Self-intersection offset after a reflection (Algorithm 2 line 7's "small initial
    // offset"), bounded by the float error of the hit point rather than fixed in mm: a
    // hit point's coordinates (at most extent_mm in this frame) carry a few ulps of
    // rounding from o + t d and from the patch root, i.e. ~4 eps extent; a reflected ray
    // leaving at an angle alpha clears that error after 8 eps extent / alpha. 128 eps
    // extent keeps every reflection steeper than ~0.06 rad clear of its own hit and skips
    // no real second hit longer than 1.5e-5 of the scene's size.
    p.offset_mm = float(128.0 * double(std::numeric_limits<float>::epsilon()) * extent_mm);
    p.source_length = float(emitter.length_mm);
    p.source_radius = float(emitter.radius_mm);
    p.source_width = float(emitter.width_mm);
    p.source_height = float(emitter.height_mm);
    p.source_kind = emitter.kind;
    p.source_table_c = emitter.table_c;
    p.source_table_g = emitter.table_g;
    p.sampler_kind = s.trace.sampler == SamplerKind::Sobol    ? gpu::kSamplerSobol
                     : s.trace.sampler == SamplerKind::Random ? gpu::kSamplerRandom
                                                              : gpu::kSamplerStratified;
    p.seed_lo = std::uint32_t(seed);
    p.seed_hi = std::uint32_t(seed >> 32);
    p.rays_lo = std::uint32_t(s.trace.rays);
    p.rays_hi = std::uint32_t(s.trace.rays >> 32);
    const SobolTables sobol = sobol_tables(seed);
    for (int d = 0; d < 4; ++d)
        for (int b = 0; b < 32; ++b)
            p.sobol_directions[d * 32 + b] = sobol.directions[d][b];
    for (int k = 0; k < 5; ++k)
        p.sobol_scramble[k] = sobol.scramble[k];

    p.hf_w = s.trace.heightfield_w;
    p.hf_h = s.trace.heightfield_h;
    const QuadtreeLayout q = quadtree_layout(p.hf_w, p.hf_h);
    p.levels = q.levels;
    for (std::uint32_t l = 0; l < q.levels; ++l) {
        p.level_w[l] = q.w[l];
        p.level_h[l] = q.h[l];
        p.level_offset[l] = q.offset[l];
    }
    p.hit_mode = s.trace.hit_mode == HitMode::Paper ? gpu::kHitModePaper : gpu::kHitModeRefined;
    p.ff_w = s.trace.farfield_w;
    p.ff_h = s.trace.farfield_h;
    p.max_bounces = s.trace.max_bounces;
    p.strict_policy = s.trace.bounce_policy == BouncePolicy::Strict ? 1u : 0u;
    const MaterialDesc& m = s.reflector.material;
    p.reflectance = float(m.reflectance);
    p.spread_rad = float(glm::radians(m.spread_deg));
    p.spread_lobe = m.lobe == SpreadLobe::Phong ? gpu::kLobePhong : gpu::kLobeGaussian;
    p.farfield_layers = farfield_layers(s);
    p.bin_direct = s.trace.direct == DirectLight::Include ? 1u : 0u;
    // A ray crosses at most W + H texels per level; generous slack for descents.
    p.max_steps = 8u * (p.hf_w + p.hf_h) + 64u * q.levels;
    return p;
}

std::uint32_t farfield_layers(const Scene& s) {
    return s.reflector.material.reflectance < 1.0 ? s.trace.max_bounces + 1u : 1u;
}

std::uint32_t gpu_family(Family family) {
    switch (family) {
    case Family::Plane:
        return gpu::kFamilyPlane;
    case Family::Paraboloid:
        return gpu::kFamilyParaboloid;
    case Family::Cup:
        return gpu::kFamilyCup;
    case Family::FlutedCup:
        return gpu::kFamilyFlutedCup;
    case Family::BSpline:
        return gpu::kFamilyBSpline;
    case Family::Mesh:
        return gpu::kFamilyTexture;
    case Family::Profile:
        return gpu::kFamilyProfile;
    }
    throw std::invalid_argument("unknown reflector family");
}

std::array<std::uint32_t, FIRD_SPEC_COUNT> specialization(const gpu::SceneParams& p,
                                                          Family family) {
    std::array<std::uint32_t, FIRD_SPEC_COUNT> spec{};
    spec[FIRD_SPEC_SOURCE_KIND] = p.source_kind;
    spec[FIRD_SPEC_SAMPLER_KIND] = p.sampler_kind;
    spec[FIRD_SPEC_FAMILY] = gpu_family(family);
    spec[FIRD_SPEC_HIT_MODE] = p.hit_mode;
    spec[FIRD_SPEC_STRICT_POLICY] = p.strict_policy;
    spec[FIRD_SPEC_SPREAD] = p.spread_rad > 0.0f ? 1u : 0u;
    return spec;
}

std::vector<float> set_reflector_params(gpu::SceneParams& p, const ReflectorDesc& r,
                                        const glm::dvec3& origin) {
    // The families' centres and base heights move into the frame; the other parameters
    // (focal lengths, slopes, exponents) do not depend on it.
    const auto get = [&](const std::string& name) {
        const double v = r.parameters.at(name);
        if (name == "cx") return float(v - origin.x);
        if (name == "cy") return float(v - origin.y);
        if (name == "z0") return float(v - origin.z);
        return float(v);
    };
    std::fill(std::begin(p.params), std::end(p.params), 0.0f);
    const auto names = family_parameters(r.family);
    p.family = gpu_family(r.family);
    if (r.family == Family::Mesh) return {}; // rasterized: no parameters
    if (r.family == Family::BSpline) {
        p.bspline_nx = std::uint32_t(r.bspline.nx);
        p.bspline_ny = std::uint32_t(r.bspline.ny);
        const auto h = bspline_heights(r.bspline, r.parameters);
        std::vector<float> control(h.size());
        for (std::size_t k = 0; k < h.size(); ++k)
            control[k] = float(h[k] - origin.z);
        return control;
    }
    if (r.family == Family::Profile) {
        // (z0, cx, cy, knot spacing) and the spline's control points, solved here in double
        // (model/surface.cpp: the one definition both tracers read). f is relative to z0,
        // which alone moves into the frame.
        const int heights = r.bspline.nx;
        p.bspline_nx = std::uint32_t(heights);
        p.bspline_ny = 1;
        p.params[0] = get("z0");
        p.params[1] = get("cx");
        p.params[2] = get("cy");
        p.params[3] = float(r.parameters.at("radius_mm") / (heights - 1));
        const auto c = profile_control_points(bspline_heights(r.bspline, r.parameters));
        return std::vector<float>(c.begin(), c.end());
    }
    for (std::size_t k = 0; k < names.size(); ++k)
        p.params[k] = get(names[k]);
    return {};
}

} // namespace fird
