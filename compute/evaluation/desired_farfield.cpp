#include "desired_farfield.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "evaluation/evaluation.hpp"
#include "evaluation/evaluator.hpp"

namespace fird {

DesiredFarField desired_farfield(const vk::Context& ctx, const Scene& scene,
                                 double reference_flux_lm, Backend backend) {
    DesiredFarField d;
    switch (scene.target.kind) {
    case TargetDesc::Kind::None:
        throw std::invalid_argument(fmt::format("{}: the scene has no [target]", scene.path));
    case TargetDesc::Kind::Reflector: {
        Fidelity f = scene_fidelity(scene);
        f.seed = scene.target.seed;
        if (scene.target.rays) f.rays = scene.target.rays;
        Evaluator target(ctx, scene, f, backend);
        (void)target.evaluate(target_reflector(scene));
        d.farfield = target.farfield();
        d.description =
            fmt::format("target reflector traced with seed {} and {} rays{}", f.seed, f.rays,
                        backend == Backend::Reference ? " by the CPU reference" : "");
        return d;
    }
    case TargetDesc::Kind::Photometric:
        d.farfield = photometric_target(scene, reference_flux_lm);
        d.scale_flux_lm = scene.target.absolute ? 0.0 : reference_flux_lm;
        d.description =
            scene.target.absolute
                ? fmt::format("{} in absolute candela", scene.target.file)
                : fmt::format("{} scaled to {:.4g} lm", scene.target.file, reference_flux_lm);
        return d;
    }
    return d;
}

} // namespace fird
