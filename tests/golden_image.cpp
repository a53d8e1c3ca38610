#include "golden_image.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <gtest/gtest.h>

#include "plot/canvas.hpp"

namespace fird::test {

namespace {

void write_rgb_png(const std::vector<std::uint8_t>& rgb, int w, int h, const std::string& path) {
    plot::Canvas cv{w, h};
    cv.image(rgb, w, h, 0, 0, w, h);
    cv.write_png(path);
}

} // namespace

void expect_like_golden(const std::vector<std::uint8_t>& rgba, int w, int h,
                        const std::string& golden, Drawn drawn) {
    namespace fs = std::filesystem;
    const std::string name = fs::path(golden).filename().string();
    if (const char* u = std::getenv("FIRD_UPDATE_GOLDENS"); u && std::string(u) == "1") {
        std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3);
        for (std::size_t i = 0; i < std::size_t(w) * h; ++i)
            for (int k = 0; k < 3; ++k)
                rgb[i * 3 + k] = rgba[i * 4 + k];
        write_rgb_png(rgb, w, h, golden);
        return;
    }
    int gw = 0, gh = 0;
    const auto g = plot::read_png_rgba(golden, gw, gh);
    ASSERT_EQ(gw, w) << name;
    ASSERT_EQ(gh, h) << name;
    std::size_t differing = 0;
    double sum = 0.0;
    std::vector<std::uint8_t> diff(std::size_t(w) * h * 3, 255);
    // Whether pixel i of `x` is within 16 in every channel of pixel j of `y`.
    const auto close = [](const std::vector<std::uint8_t>& x, std::size_t i,
                          const std::vector<std::uint8_t>& y, std::size_t j) {
        for (int k = 0; k < 3; ++k)
            if (std::abs(int(x[i * 4 + k]) - int(y[j * 4 + k])) > 16) return false;
        return true;
    };
    // Whether pixel (x, y) of `a` matches a pixel of `b` within one pixel.
    const auto near = [&](const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b,
                          int x, int y) {
        const std::size_t i = std::size_t(y) * w + x;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int yy = y + dy, xx = x + dx;
                if (yy >= 0 && yy < h && xx >= 0 && xx < w &&
                    close(a, i, b, std::size_t(yy) * w + xx))
                    return true;
            }
        return false;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * w + x;
            for (int k = 0; k < 3; ++k)
                sum += std::abs(int(rgba[i * 4 + k]) - int(g[i * 4 + k]));
            if (close(rgba, i, g, i)) continue;
            if (drawn == Drawn::OnDevice && near(rgba, g, x, y) && near(g, rgba, x, y)) continue;
            ++differing;
            diff[i * 3] = 220, diff[i * 3 + 1] = diff[i * 3 + 2] = 0;
        }
    const double mean = sum / (3.0 * w * h);
    const bool ok = differing <= std::size_t(0.005 * w * h) && mean < 1.5;
    EXPECT_TRUE(ok) << name << ": " << differing << " pixels differ, mean difference " << mean;
    if (!ok) {
        const auto out = fs::path(::testing::TempDir()) / ("diff_" + name);
        write_rgb_png(diff, w, h, out.string());
        std::fprintf(stderr, "diff image: %s\n", out.c_str());
    }
}

} // namespace fird::test
