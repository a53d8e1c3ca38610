// A 2D drawing surface on cairo: antialiased lines, filled shapes, text in a real font
// (DejaVu Sans), images; written to PNG or handed over as RGBA pixels (the workbench
// uploads those as a texture). The one place FIRD draws pictures.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace fird::plot {

struct Colour {
    double r = 0, g = 0, b = 0, a = 1;
};
inline constexpr Colour kInk{0.1, 0.1, 0.1};
inline constexpr Colour kGrid{0.86, 0.86, 0.86};
inline constexpr Colour kWhite{1, 1, 1};

enum class Align { Left, Centre, Right };

struct Point {
    double x = 0, y = 0;
};

struct Stroke {
    Colour colour = kInk;
    double width = 1.5;
    bool dashed = false;
};

// A PNG read back as non-premultiplied RGBA (for golden-image tests); errors name it.
std::vector<std::uint8_t> read_png_rgba(const std::string& path, int& width, int& height);

class Canvas {
  public:
    Canvas(int width, int height, Colour background = kWhite);
    ~Canvas();
    Canvas(Canvas&&) noexcept;
    Canvas& operator=(Canvas&&) noexcept;
    Canvas(const Canvas&) = delete;
    Canvas& operator=(const Canvas&) = delete;

    int width() const { return width_; }
    int height() const { return height_; }

    void polyline(const std::vector<Point>& points, const Stroke& stroke);
    void line(Point a, Point b, const Stroke& stroke) { polyline({a, b}, stroke); }
    void fill_polygon(const std::vector<Point>& points, Colour colour);
    void fill_rect(double x, double y, double w, double h, Colour colour);
    void stroke_rect(double x, double y, double w, double h, const Stroke& stroke);
    void fill_circle(Point centre, double radius, Colour colour);
    // Text with its baseline's anchor at (x, y); `angle_deg` turns it counter-clockwise.
    void text(double x, double y, const std::string& s, double size_px, Align align = Align::Left,
              Colour colour = kInk, double angle_deg = 0.0, bool bold = false);
    double text_width(const std::string& s, double size_px, bool bold = false);
    // An RGB image (3 bytes per pixel, rows top down) scaled into the rectangle, each
    // source pixel a sharp block (no smoothing across far-field cells).
    void image(const std::vector<std::uint8_t>& rgb, int w, int h, double x, double y, double dw,
               double dh);
    // Restricts drawing to the rectangle until unclip().
    void clip(double x, double y, double w, double h);
    void unclip();

    // PNG, written to a temporary name and renamed (io/atomic_file); errors name the path.
    void write_png(const std::string& path);
    // Non-premultiplied RGBA, rows top down.
    std::vector<std::uint8_t> rgba();

  private:
    struct State;
    std::unique_ptr<State> state_;
    int width_ = 0, height_ = 0;
};

} // namespace fird::plot
