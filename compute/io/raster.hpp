// A small RGB raster for report images: rectangles, text (stb_easy_font), PNG output.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fird {

using Rgb = std::array<std::uint8_t, 3>;

struct Raster {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgb;

    Raster(int w, int h, Rgb background);
    void set(int x, int y, Rgb c);
    void fill_rect(int x0, int y0, int x1, int y1, Rgb c); // [x0, x1) x [y0, y1)
    // Draws text with its top-left corner at (x, y), `scale` pixels per font unit.
    void text(int x, int y, const std::string& s, Rgb c, int scale = 2);
    static int text_width(const std::string& s, int scale = 2);
    void write_png(const std::string& path) const; // throws with the path on failure
};

// Perceptual-ish sequential map (black - purple - orange - yellow - white), t in [0, 1].
Rgb sequential_colour(double t);
// Diverging map (blue - white - red), t in [-1, 1].
Rgb diverging_colour(double t);

} // namespace fird
