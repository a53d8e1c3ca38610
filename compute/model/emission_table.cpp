#include "emission_table.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fird {

EmissionTable emission_table(const CandelaTable& t) {
    const std::size_t nc = t.c_deg.size() + 1, ng = t.gamma_deg.size();
    if (t.c_deg.empty() || ng < 2)
        throw std::invalid_argument("the distribution needs two gamma angles or more");
    std::vector<float> f;
    f.reserve(nc + ng + nc * ng + (nc - 1) * (ng - 1));
    const double to_rad = std::numbers::pi / 180.0;
    for (const double c : t.c_deg)
        f.push_back(float(c * to_rad));
    f.push_back(float((t.c_deg.front() + 360.0) * to_rad));
    std::vector<double> mu;
    for (const double g : t.gamma_deg) {
        mu.push_back(std::cos(g * to_rad));
        f.push_back(float(mu.back()));
    }
    const auto cd = [&](std::size_t j, std::size_t i) { return t.at(j % t.c_deg.size(), i); };
    for (std::size_t j = 0; j < nc; ++j)
        for (std::size_t i = 0; i < ng; ++i)
            f.push_back(float(cd(j, i)));
    // A cell's flux: its solid angle dC dcos(gamma) times the mean of its corners (the
    // exact integral of a bilinear function), summed in double.
    std::vector<double> cumulative;
    double total = 0.0;
    for (std::size_t j = 0; j + 1 < nc; ++j) {
        const double c0 = t.c_deg[j];
        const double c1 = j + 1 < t.c_deg.size() ? t.c_deg[j + 1] : t.c_deg.front() + 360.0;
        for (std::size_t i = 0; i + 1 < ng; ++i) {
            const double corners = cd(j, i) + cd(j, i + 1) + cd(j + 1, i) + cd(j + 1, i + 1);
            total += (c1 - c0) * to_rad * (mu[i] - mu[i + 1]) * 0.25 * corners;
            cumulative.push_back(total);
        }
    }
    if (!(total > 0.0)) throw std::invalid_argument("the distribution emits no flux");
    for (const double c : cumulative)
        f.push_back(float(c / total));
    f.back() = 1.0f; // the last cell ends the distribution, whatever the rounding
    return {.floats = std::make_shared<const std::vector<float>>(std::move(f)),
            .c_angles = std::uint32_t(nc),
            .gamma_angles = std::uint32_t(ng)};
}

} // namespace fird
