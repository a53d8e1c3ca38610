#include "farfield_png.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "raster.hpp"

namespace fird {

void write_farfield_png(const std::string& path, const FarField& f,
                        const FarFieldImageOptions& options) {
    // At most 1800 x 900 pixels of map; each pixel shows the largest |value| of its cells,
    // so narrow peaks are not lost when the grid is finer than the image.
    const int map_w = int(std::min<std::uint32_t>(f.width, 1800));
    const int map_h = int(std::min<std::uint32_t>(f.height, 900));
    constexpr int kLeft = 90, kTop = 40, kBottom = 60, kBarGap = 60, kBarW = 30, kRight = 130;
    Raster img(kLeft + map_w + kBarGap + kBarW + kRight, kTop + map_h + kBottom, {255, 255, 255});
    const Rgb ink{20, 20, 20};

    double peak = 0.0;
    for (double v : f.lm)
        peak = std::max(peak, std::abs(v));
    const double scale = peak > 0.0 ? 1.0 / peak : 0.0;
    for (int py = 0; py < map_h; ++py)
        for (int px = 0; px < map_w; ++px) {
            const std::uint32_t r0 = std::uint32_t(std::uint64_t(py) * f.height / map_h);
            const std::uint32_t r1 =
                std::max(r0 + 1, std::uint32_t(std::uint64_t(py + 1) * f.height / map_h));
            const std::uint32_t c0 = std::uint32_t(std::uint64_t(px) * f.width / map_w);
            const std::uint32_t c1 =
                std::max(c0 + 1, std::uint32_t(std::uint64_t(px + 1) * f.width / map_w));
            double v = 0.0;
            for (std::uint32_t r = r0; r < r1; ++r)
                for (std::uint32_t c = c0; c < c1; ++c) {
                    const double x = f.lm[std::size_t(r) * f.width + c];
                    if (std::abs(x) > std::abs(v)) v = x;
                }
            img.set(kLeft + px, kTop + py,
                    options.signed_values ? diverging_colour(v * scale)
                                          : sequential_colour(v * scale));
        }

    // Axes: altitude on the left, azimuth below, in degrees.
    for (int deg = -90; deg <= 90; deg += 45) {
        const int y = kTop + int(std::lround((90.0 - deg) / 180.0 * (map_h - 1)));
        img.fill_rect(kLeft - 8, y, kLeft, y + 1, ink);
        const std::string label = fmt::format("{:+d}", deg);
        img.text(kLeft - 12 - Raster::text_width(label), y - 6, label, ink);
    }
    for (int deg = -180; deg <= 180; deg += 45) {
        const int x = kLeft + int(std::lround((deg + 180.0) / 360.0 * (map_w - 1)));
        img.fill_rect(x, kTop + map_h, x + 1, kTop + map_h + 8, ink);
        const std::string label = std::to_string(deg);
        img.text(x - Raster::text_width(label) / 2, kTop + map_h + 12, label, ink);
    }
    img.text(kLeft, kTop + map_h + 34, "azimuth phi (deg)", ink);
    img.text(4, kTop - 30, "altitude theta (deg)", ink);
    img.text(kLeft + 300, 8,
             fmt::format("{}   {} x {} cells, total {:.4g} lm", options.title, f.width, f.height,
                         f.total_lm()),
             ink);

    // Colour bar with its end values.
    const int bx = kLeft + map_w + kBarGap;
    for (int y = 0; y < map_h; ++y) {
        const double t = 1.0 - double(y) / (map_h - 1);
        const Rgb c =
            options.signed_values ? diverging_colour(2.0 * t - 1.0) : sequential_colour(t);
        img.fill_rect(bx, kTop + y, bx + kBarW, kTop + y + 1, c);
    }
    const double low = options.signed_values ? -peak : 0.0;
    img.text(bx + kBarW + 6, kTop - 4, fmt::format("{:.3g} lm", peak), ink);
    img.text(bx + kBarW + 6, kTop + map_h - 10, fmt::format("{:.3g} lm", low), ink);
    img.text(bx - 10, kTop + map_h + 12, "per cell", ink);
    img.write_png(path);
}

} // namespace fird
