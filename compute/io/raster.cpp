#include "raster.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <stb_easy_font.h>
#include <stb_image_write.h>

namespace fird {

Raster::Raster(int w, int h, Rgb background) : width(w), height(h), rgb(std::size_t(w) * h * 3) {
    for (std::size_t i = 0; i < rgb.size(); i += 3)
        std::copy(background.begin(), background.end(), rgb.begin() + std::ptrdiff_t(i));
}

void Raster::set(int x, int y, Rgb c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const std::size_t i = (std::size_t(y) * width + x) * 3;
    rgb[i] = c[0];
    rgb[i + 1] = c[1];
    rgb[i + 2] = c[2];
}

void Raster::fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
    for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
        for (int x = std::max(x0, 0); x < std::min(x1, width); ++x)
            set(x, y, c);
}

void Raster::text(int x, int y, const std::string& s, Rgb c, int scale) {
    // stb_easy_font emits axis-aligned quads (4 vertices of 16 bytes each).
    std::vector<char> buffer(s.size() * 270 + 64);
    std::string copy = s;
    unsigned char colour[4] = {c[0], c[1], c[2], 255};
    const int quads =
        stb_easy_font_print(0, 0, copy.data(), colour, buffer.data(), int(buffer.size()));
    for (int q = 0; q < quads; ++q) {
        const float* v = reinterpret_cast<const float*>(buffer.data() + q * 64);
        const float qx0 = v[0], qy0 = v[1], qx1 = v[8], qy1 = v[9]; // vertices 0 and 2
        const auto at = [scale](float coord) { return int(coord * float(scale)); };
        fill_rect(x + at(qx0), y + at(qy0), x + at(qx1), y + at(qy1), c);
    }
}

int Raster::text_width(const std::string& s, int scale) {
    std::string copy = s;
    return stb_easy_font_width(copy.data()) * scale;
}

void Raster::write_png(const std::string& path) const {
    if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
        throw std::runtime_error(path + ": cannot write PNG");
}

namespace {
Rgb lerp_stops(const std::vector<std::array<double, 4>>& stops, double t) {
    t = std::clamp(t, 0.0, 1.0);
    for (std::size_t i = 1; i < stops.size(); ++i)
        if (t <= stops[i][0]) {
            const auto& a = stops[i - 1];
            const auto& b = stops[i];
            const double f = (t - a[0]) / (b[0] - a[0]);
            Rgb c;
            for (int k = 0; k < 3; ++k)
                c[k] = std::uint8_t(std::lround(255.0 * (a[k + 1] + f * (b[k + 1] - a[k + 1]))));
            return c;
        }
    return {255, 255, 255};
}
} // namespace

Rgb sequential_colour(double t) {
    static const std::vector<std::array<double, 4>> stops = {
        {0.0, 0.0, 0.0, 0.0},     {0.25, 0.30, 0.05, 0.45}, {0.5, 0.75, 0.15, 0.35},
        {0.75, 0.98, 0.55, 0.05}, {0.92, 1.0, 0.92, 0.35},  {1.0, 1.0, 1.0, 1.0}};
    return lerp_stops(stops, t);
}

Rgb diverging_colour(double t) {
    static const std::vector<std::array<double, 4>> stops = {
        {0.0, 0.10, 0.25, 0.75}, {0.5, 1.0, 1.0, 1.0}, {1.0, 0.75, 0.10, 0.10}};
    return lerp_stops(stops, 0.5 * (std::clamp(t, -1.0, 1.0) + 1.0));
}

} // namespace fird
