#include "candela_table.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>

namespace fird {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;

// The stored gamma interval holding `gamma` and the weight of its upper end (linear in
// cos gamma); false outside the stored range.
bool gamma_interval(const std::vector<double>& g, double gamma, std::size_t& i, double& w) {
    if (gamma < g.front() || gamma > g.back()) return false;
    if (g.size() == 1) {
        i = 0;
        w = 0.0;
        return true;
    }
    i = std::size_t(std::upper_bound(g.begin(), g.end(), gamma) - g.begin());
    i = std::min(std::max<std::size_t>(i, 1), g.size() - 1) - 1;
    const double u0 = std::cos(g[i] * kDeg), u1 = std::cos(g[i + 1] * kDeg);
    w = std::clamp((u0 - std::cos(gamma * kDeg)) / (u0 - u1), 0.0, 1.0);
    return true;
}

// The C interval (wrapping at 360) holding `c` and the weight of its upper plane.
void c_interval(const std::vector<double>& cs, double c, std::size_t& k, std::size_t& k1,
                double& w) {
    if (cs.size() == 1) {
        k = k1 = 0;
        w = 0.0;
        return;
    }
    c = std::fmod(c, 360.0);
    if (c < 0.0) c += 360.0;
    auto it = std::upper_bound(cs.begin(), cs.end(), c);
    if (it == cs.begin()) { // before the first plane: between the last and the first
        k = cs.size() - 1;
        k1 = 0;
        const double span = cs.front() + 360.0 - cs.back();
        w = (c + 360.0 - cs.back()) / span;
        return;
    }
    k = std::size_t(it - cs.begin()) - 1;
    k1 = (k + 1) % cs.size();
    const double hi = k1 == 0 ? cs.front() + 360.0 : cs[k1];
    w = (c - cs[k]) / (hi - cs[k]);
}
} // namespace

const char* to_string(PhotometricType type) {
    switch (type) {
    case PhotometricType::A:
        return "A";
    case PhotometricType::B:
        return "B";
    case PhotometricType::C:
        return "C";
    }
    return "?";
}

const char* to_string(Symmetry symmetry) {
    switch (symmetry) {
    case Symmetry::None:
        return "none";
    case Symmetry::Rotational:
        return "rotational";
    case Symmetry::C0C180:
        return "c0-c180";
    case Symmetry::C90C270:
        return "c90-c270";
    case Symmetry::Quadrant:
        return "quadrant";
    }
    return "?";
}

double CandelaTable::peak_cd() const {
    return cd.empty() ? 0.0 : *std::max_element(cd.begin(), cd.end());
}

double intensity_cd(const CandelaTable& t, double c_deg, double gamma_deg) {
    std::size_t i = 0, k = 0, k1 = 0;
    double wg = 0.0, wc = 0.0;
    if (!gamma_interval(t.gamma_deg, gamma_deg, i, wg)) return 0.0;
    c_interval(t.c_deg, c_deg, k, k1, wc);
    const std::size_t i1 = std::min(i + 1, t.gamma_deg.size() - 1);
    const double a = (1.0 - wg) * t.at(k, i) + wg * t.at(k, i1);
    const double b = (1.0 - wg) * t.at(k1, i) + wg * t.at(k1, i1);
    return (1.0 - wc) * a + wc * b;
}

double integrated_flux_lm(const CandelaTable& t) {
    const std::size_t nc = t.c_deg.size(), ng = t.gamma_deg.size();
    double flux = 0.0;
    for (std::size_t k = 0; k < nc; ++k) {
        // This plane's share of the azimuth: half of each neighbouring C interval.
        double width_deg = 360.0;
        if (nc > 1) {
            const double next = k + 1 < nc ? t.c_deg[k + 1] : t.c_deg[0] + 360.0;
            const double prev = k > 0 ? t.c_deg[k - 1] : t.c_deg[nc - 1] - 360.0;
            width_deg = 0.5 * (next - prev);
        }
        double zone = 0.0;
        for (std::size_t g = 0; g + 1 < ng; ++g)
            zone += 0.5 * (t.at(k, g) + t.at(k, g + 1)) *
                    (std::cos(t.gamma_deg[g] * kDeg) - std::cos(t.gamma_deg[g + 1] * kDeg));
        flux += width_deg * kDeg * zone;
    }
    return flux;
}

void expand_symmetry(CandelaTable& t, const std::vector<double>& stored_c,
                     const std::vector<std::vector<double>>& planes) {
    // Planes keyed by their angle in [0, 360), rounded so that mirrored copies of the
    // same angle meet; the stored planes go in first, so they win over mirrored copies.
    std::map<long long, std::pair<double, const std::vector<double>*>> full;
    const auto key = [](double c) { return std::llround(c * 1e6); };
    const auto put = [&](double c, const std::vector<double>& plane) {
        c = std::fmod(c, 360.0);
        if (c < 0.0) c += 360.0;
        if (key(c) == key(360.0)) c = 0.0;
        full.try_emplace(key(c), c, &plane);
    };
    if (t.symmetry == Symmetry::Rotational) {
        put(0.0, planes.front());
    } else {
        for (std::size_t p = 0; p < stored_c.size(); ++p)
            put(stored_c[p], planes[p]);
        for (std::size_t p = 0; p < stored_c.size(); ++p) {
            const double c = stored_c[p];
            switch (t.symmetry) {
            case Symmetry::C0C180: // mirror across the C0-C180 plane
                put(360.0 - c, planes[p]);
                break;
            case Symmetry::C90C270: // mirror across the C90-C270 plane
                put(180.0 - c, planes[p]);
                break;
            case Symmetry::Quadrant:
                put(180.0 - c, planes[p]);
                put(180.0 + c, planes[p]);
                put(360.0 - c, planes[p]);
                break;
            default:
                break;
            }
        }
    }
    t.c_deg.clear();
    t.cd.clear();
    for (const auto& [k, entry] : full) {
        t.c_deg.push_back(entry.first);
        t.cd.insert(t.cd.end(), entry.second->begin(), entry.second->end());
    }
}

void resample_to_type_c(CandelaTable& table, PhotometricType type,
                        const std::function<double(double, double)>& sample) {
    table.gamma_deg.clear();
    for (int g = 0; g <= 360; ++g)
        table.gamma_deg.push_back(0.5 * g);
    table.c_deg.clear();
    for (int c = 0; c < 360; ++c)
        table.c_deg.push_back(c);
    table.cd.assign(table.c_deg.size() * table.gamma_deg.size(), 0.0);
    for (std::size_t c = 0; c < table.c_deg.size(); ++c)
        for (std::size_t g = 0; g < table.gamma_deg.size(); ++g) {
            const double sg = std::sin(table.gamma_deg[g] * kDeg);
            const double x = sg * std::cos(table.c_deg[c] * kDeg);
            const double y = sg * std::sin(table.c_deg[c] * kDeg);
            const double z = -std::cos(table.gamma_deg[g] * kDeg);
            double h = 0.0, v = 0.0;
            if (type == PhotometricType::B) {
                h = std::asin(std::clamp(y, -1.0, 1.0)) / kDeg;
                v = std::atan2(x, -z) / kDeg;
            } else {
                v = std::asin(std::clamp(z, -1.0, 1.0)) / kDeg;
                h = std::atan2(-y, x) / kDeg;
            }
            table.cd[c * table.gamma_deg.size() + g] = sample(h, v);
        }
}

} // namespace fird
