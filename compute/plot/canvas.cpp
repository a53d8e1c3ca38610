#include "canvas.hpp"

#include <cairo.h>

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fird::plot {

// The font every picture uses: installed with fonts-dejavu-core (scripts/setup.sh), so
// pictures, and the golden images that test them, look the same on every machine.
constexpr const char* kFont = "DejaVu Sans";

struct Canvas::State {
    cairo_surface_t* surface = nullptr;
    cairo_t* cr = nullptr;
    ~State() {
        if (cr) cairo_destroy(cr);
        if (surface) cairo_surface_destroy(surface);
    }
};

namespace {
void set(cairo_t* cr, Colour c) {
    cairo_set_source_rgba(cr, c.r, c.g, c.b, c.a);
}
void path(cairo_t* cr, const std::vector<Point>& points) {
    cairo_new_path(cr);
    for (std::size_t i = 0; i < points.size(); ++i)
        if (std::isfinite(points[i].x) && std::isfinite(points[i].y))
            (i == 0 ? cairo_move_to : cairo_line_to)(cr, points[i].x, points[i].y);
}
} // namespace

Canvas::Canvas(int width, int height, Colour background)
    : state_(std::make_unique<State>()), width_(width), height_(height) {
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
        throw std::invalid_argument(fmt::format("a picture of {} x {} pixels", width, height));
    state_->surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height);
    state_->cr = cairo_create(state_->surface);
    if (cairo_status(state_->cr) != CAIRO_STATUS_SUCCESS)
        throw std::runtime_error("cairo: cannot create a drawing surface");
    cairo_select_font_face(state_->cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    fill_rect(0, 0, width, height, background);
}

Canvas::~Canvas() = default;
Canvas::Canvas(Canvas&&) noexcept = default;
Canvas& Canvas::operator=(Canvas&&) noexcept = default;

void Canvas::polyline(const std::vector<Point>& points, const Stroke& s) {
    cairo_t* cr = state_->cr;
    path(cr, points);
    set(cr, s.colour);
    cairo_set_line_width(cr, s.width);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    const double dash[] = {6.0, 4.0};
    cairo_set_dash(cr, dash, s.dashed ? 2 : 0, 0.0);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0.0);
}

void Canvas::fill_polygon(const std::vector<Point>& points, Colour c) {
    path(state_->cr, points);
    cairo_close_path(state_->cr);
    set(state_->cr, c);
    cairo_fill(state_->cr);
}

void Canvas::fill_rect(double x, double y, double w, double h, Colour c) {
    cairo_new_path(state_->cr);
    cairo_rectangle(state_->cr, x, y, w, h);
    set(state_->cr, c);
    cairo_fill(state_->cr);
}

void Canvas::stroke_rect(double x, double y, double w, double h, const Stroke& s) {
    polyline({{x, y}, {x + w, y}, {x + w, y + h}, {x, y + h}, {x, y}}, s);
}

void Canvas::fill_circle(Point c, double radius, Colour colour) {
    cairo_new_path(state_->cr);
    cairo_arc(state_->cr, c.x, c.y, radius, 0.0, 2.0 * M_PI);
    set(state_->cr, colour);
    cairo_fill(state_->cr);
}

double Canvas::text_width(const std::string& s, double size_px, bool bold) {
    cairo_t* cr = state_->cr;
    cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size_px);
    cairo_text_extents_t e;
    cairo_text_extents(cr, s.c_str(), &e);
    return e.x_advance;
}

void Canvas::text(double x, double y, const std::string& s, double size_px, Align align,
                  Colour colour, double angle_deg, bool bold) {
    cairo_t* cr = state_->cr;
    const double w = text_width(s, size_px, bold);
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_rotate(cr, -angle_deg * M_PI / 180.0);
    const double dx = align == Align::Left ? 0.0 : align == Align::Centre ? -0.5 * w : -w;
    cairo_move_to(cr, dx, 0.0);
    set(cr, colour);
    cairo_show_text(cr, s.c_str());
    cairo_restore(cr);
}

void Canvas::image(const std::vector<std::uint8_t>& rgb, int w, int h, double x, double y,
                   double dw, double dh) {
    if (w <= 0 || h <= 0 || rgb.size() < std::size_t(w) * h * 3) return;
    cairo_surface_t* img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_surface_flush(img);
    unsigned char* data = cairo_image_surface_get_data(img);
    const int stride = cairo_image_surface_get_stride(img);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::uint8_t* p = &rgb[(std::size_t(j) * w + i) * 3];
            auto* q = reinterpret_cast<std::uint32_t*>(data + std::size_t(j) * stride) + i;
            *q = (std::uint32_t(p[0]) << 16) | (std::uint32_t(p[1]) << 8) | p[2];
        }
    cairo_surface_mark_dirty(img);
    cairo_t* cr = state_->cr;
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, dw / w, dh / h);
    cairo_set_source_surface(cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_rectangle(cr, 0, 0, w, h);
    cairo_fill(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);
}

void Canvas::clip(double x, double y, double w, double h) {
    cairo_save(state_->cr);
    cairo_new_path(state_->cr);
    cairo_rectangle(state_->cr, x, y, w, h);
    cairo_clip(state_->cr);
}

void Canvas::unclip() {
    cairo_restore(state_->cr);
}

void Canvas::write_png(const std::string& out) {
    cairo_surface_flush(state_->surface);
    write_atomically(out, [&](const std::string& temporary) {
        if (cairo_surface_write_to_png(state_->surface, temporary.c_str()) != CAIRO_STATUS_SUCCESS)
            throw std::runtime_error(fmt::format("{}: cannot write PNG", out));
    });
}

namespace {
std::vector<std::uint8_t> surface_rgba(cairo_surface_t* surface, int w, int h) {
    cairo_surface_flush(surface);
    const unsigned char* data = cairo_image_surface_get_data(surface);
    const int stride = cairo_image_surface_get_stride(surface);
    const bool alpha = cairo_image_surface_get_format(surface) == CAIRO_FORMAT_ARGB32;
    std::vector<std::uint8_t> out(std::size_t(w) * h * 4);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const std::uint32_t p =
                reinterpret_cast<const std::uint32_t*>(data + std::size_t(j) * stride)[i];
            const std::uint32_t a = alpha ? p >> 24 : 255;
            std::uint8_t* q = &out[(std::size_t(j) * w + i) * 4];
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t c = (p >> (16 - 8 * k)) & 0xff; // premultiplied
                q[k] = std::uint8_t(a ? std::min<std::uint32_t>(255, (c * 255 + a / 2) / a) : 0);
            }
            q[3] = std::uint8_t(a);
        }
    return out;
}
} // namespace

std::vector<std::uint8_t> read_png_rgba(const std::string& path, int& width, int& height) {
    cairo_surface_t* s = cairo_image_surface_create_from_png(path.c_str());
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        throw std::runtime_error(fmt::format("{}: cannot read it as PNG", path));
    }
    width = cairo_image_surface_get_width(s);
    height = cairo_image_surface_get_height(s);
    auto out = surface_rgba(s, width, height);
    cairo_surface_destroy(s);
    return out;
}

std::vector<std::uint8_t> Canvas::rgba() {
    return surface_rgba(state_->surface, width_, height_);
}

} // namespace fird::plot
