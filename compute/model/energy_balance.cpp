#include "energy_balance.hpp"

namespace fird {

namespace {
// Sum over reflection counts k of n_k R^k, in rays.
double weighed(const std::vector<std::uint64_t>& by_reflections, double reflectance) {
    double sum = 0.0, weight = 1.0;
    for (const std::uint64_t n : by_reflections) {
        sum += double(n) * weight;
        weight *= reflectance;
    }
    return sum;
}
} // namespace

EnergyBalance energy_balance(const RayTally& t, double lm_per_ray) {
    EnergyBalance e;
    e.emitted_lm = double(t.emitted) * lm_per_ray;
    e.direct_lm = double(t.direct) * lm_per_ray;
    e.discarded_lm = double(t.discarded) * lm_per_ray;
    if (t.reflectance == 1.0) { // a perfect mirror keeps every ray's whole flux
        e.farfield_lm = double(t.farfield) * lm_per_ray;
        e.lost_lm = double(t.lost) * lm_per_ray;
    } else {
        e.farfield_lm = weighed(t.by_reflections, t.reflectance) * lm_per_ray;
        e.lost_lm = weighed(t.lost_by_reflections, t.reflectance) * lm_per_ray;
        // What the reflections took: the far-field and lost rays' flux less what they kept.
        e.absorbed_lm = double(t.farfield + t.lost) * lm_per_ray - e.farfield_lm - e.lost_lm;
    }
    e.binned_lm = e.farfield_lm + (t.direct_binned ? e.direct_lm : 0.0);
    return e;
}

} // namespace fird
