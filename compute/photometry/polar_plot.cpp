#include "polar_plot.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "io/raster.hpp"

namespace fird {

namespace {

void line(Raster& img, double x0, double y0, double x1, double y1, Rgb c) {
    const int n = int(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int k = 0; k <= n; ++k) {
        const double t = double(k) / n;
        const int x = int(std::lround(x0 + t * (x1 - x0))),
                  y = int(std::lround(y0 + t * (y1 - y0)));
        if (x >= 0 && y >= 0 && x < img.width && y < img.height) {
            img.set(x, y, c);
            if (x + 1 < img.width) img.set(x + 1, y, c); // two pixels wide
        }
    }
}

} // namespace

void write_polar_plot_png(const std::string& path, const CandelaTable& t) {
    constexpr int kSize = 640, kMargin = 60;
    constexpr double kDeg = std::numbers::pi / 180.0;
    Raster img(kSize, kSize + 40, {255, 255, 255});
    const double cx = kSize / 2.0, cy = kSize / 2.0, radius = kSize / 2.0 - kMargin;
    const double peak = t.peak_cd();
    const Rgb grid{200, 200, 200}, ink{20, 20, 20};
    // Rings at quarters of the peak; spokes every 30 deg of gamma.
    for (int ring = 1; ring <= 4; ++ring) {
        const double r = radius * ring / 4.0;
        for (int k = 0; k < 720; ++k)
            line(img, cx + r * std::cos(k * 0.5 * kDeg), cy + r * std::sin(k * 0.5 * kDeg),
                 cx + r * std::cos((k + 1) * 0.5 * kDeg), cy + r * std::sin((k + 1) * 0.5 * kDeg),
                 grid);
        img.text(int(cx + 4), int(cy - r - 14), fmt::format("{:.4g}", peak * ring / 4.0), ink, 1);
    }
    for (int a = 0; a < 360; a += 30)
        line(img, cx, cy, cx + radius * std::sin(a * kDeg), cy + radius * std::cos(a * kDeg), grid);
    // Gamma 0 (nadir) points down the picture; each plane pair spans left (C180 / C270)
    // and right (C0 / C90).
    const struct {
        double right_c, left_c;
        Rgb colour;
        const char* label;
    } planes[] = {{0.0, 180.0, {200, 40, 40}, "C0-C180"}, {90.0, 270.0, {40, 80, 200}, "C90-C270"}};
    for (const auto& p : planes) {
        double px = 0.0, py = 0.0;
        for (int k = 0; k <= 720; ++k) {
            const double a = k * 0.5; // -180 .. 180 around the picture, 0 = nadir
            const double signed_gamma = a - 180.0;
            const double gamma = std::abs(signed_gamma);
            const double c = signed_gamma >= 0.0 ? p.right_c : p.left_c;
            const double r = peak > 0.0 ? radius * intensity_cd(t, c, gamma) / peak : 0.0;
            const double x = cx + r * std::sin(signed_gamma * kDeg);
            const double y = cy + r * std::cos(signed_gamma * kDeg);
            if (k > 0) line(img, px, py, x, y, p.colour);
            px = x;
            py = y;
        }
    }
    img.text(10, 10, "candela, principal planes (gamma 0 = nadir, down)", ink, 2);
    img.fill_rect(10, kSize + 8, 40, kSize + 14, planes[0].colour);
    img.text(46, kSize + 4, planes[0].label, ink, 2);
    img.fill_rect(200, kSize + 8, 230, kSize + 14, planes[1].colour);
    img.text(236, kSize + 4, planes[1].label, ink, 2);
    img.write_png(path);
}

} // namespace fird
