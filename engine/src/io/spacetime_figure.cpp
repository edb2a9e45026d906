#include "spacetime_figure.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "colormap.hpp"

namespace compaction {

namespace {

constexpr int kWidth = 900, kHeight = 440;
constexpr double kLeft = 72, kRight = 96, kTop = 16, kBottom = 52;  // margins [px]
constexpr const char* kFont = "DejaVu Sans";

using Context = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;
using Surface = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

// Ticks at 1, 2 or 5 times a power of ten, about `count` of them across [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int count) {
  std::vector<double> out;
  if (!(hi > lo)) return out;
  const double raw = (hi - lo) / count;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
  for (double t = std::ceil(lo / step - 1e-9) * step; t <= hi + step * 1e-9; t += step) {
    out.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  }
  return out;
}

std::string tick_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void text(cairo_t* cr, const std::string& s, double x, double y, double size, double align_x,
          double align_y, double angle = 0.0) {
  cairo_save(cr);
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  cairo_move_to(cr, -e.x_bearing - align_x * e.width, -e.y_bearing - align_y * e.height);
  cairo_show_text(cr, s.c_str());
  cairo_restore(cr);
}

// The map as a frames x rows image, height up; rows above the top plate transparent.
Surface map_image(const SpaceTimeMap& m, const std::vector<double>& eps, double h0, double vmax) {
  Surface s(cairo_image_surface_create(CAIRO_FORMAT_ARGB32, m.n_frames, m.n_rows),
            &cairo_surface_destroy);
  cairo_surface_flush(s.get());
  unsigned char* data = cairo_image_surface_get_data(s.get());
  const int stride = cairo_image_surface_get_stride(s.get());
  for (int f = 0; f < m.n_frames; ++f) {
    // Rows whose bottom is at or above the top plate, h0 (1 - eps), hold no particles.
    const double e = f < static_cast<int>(eps.size()) ? eps[f] : 0.0;
    const int first_empty = static_cast<int>(std::ceil((1.0 - e) * h0 / m.row_height - 1e-9));
    for (int r = 0; r < m.n_rows; ++r) {
      auto* px = reinterpret_cast<std::uint32_t*>(data + (m.n_rows - 1 - r) * stride) + f;
      if (r >= first_empty && m.row_height > 0) {
        *px = 0;
        continue;
      }
      const Rgb c = inferno(std::log10(1.0 + std::max(0.0f, m.at(f, r))) / vmax);
      *px = 0xff000000u | (std::uint32_t{c.r} << 16) | (std::uint32_t{c.g} << 8) | c.b;
    }
  }
  cairo_surface_mark_dirty(s.get());
  return s;
}

}  // namespace

void write_spacetime_figure(const std::filesystem::path& path, const SpaceTimeMap& m,
                            const std::vector<double>& frame_eps, double h0) {
  if (m.n_frames == 0 || m.n_rows == 0) return;
  // Colour: log10(1 + value), clipped at the 99.5th percentile so that one spike does not wash
  // the map out (the run page's rule).
  std::vector<float> logs;
  logs.reserve(m.values.size());
  for (float v : m.values) logs.push_back(static_cast<float>(std::log10(1.0 + std::max(0.0f, v))));
  std::vector<float> sorted = logs;
  const std::size_t k = static_cast<std::size_t>(0.995 * (sorted.size() - 1));
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  const double vmax = std::max(1e-6, static_cast<double>(sorted[k]));

  const double eps1 = frame_eps.empty() ? 1.0 : frame_eps.back();
  const double d_eps = frame_eps.size() > 1 ? (frame_eps.back() - frame_eps.front()) / (frame_eps.size() - 1)
                                            : eps1;
  const double eps0 = std::max(0.0, eps1 - d_eps * m.n_frames);
  const double top = m.n_rows * m.row_height / h0;

  Surface surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, kWidth, kHeight), &cairo_surface_destroy);
  Context cr(cairo_create(surface.get()), &cairo_destroy);
  cairo_t* c = cr.get();
  cairo_set_source_rgb(c, 1, 1, 1);
  cairo_paint(c);

  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  auto px = [&](double eps) { return kLeft + (eps - eps0) / (eps1 - eps0) * pw; };
  auto py = [&](double y) { return kTop + ph - y / top * ph; };

  // The map, scaled to the plot (nearest neighbour: a frame or a row is a block).
  Surface img = map_image(m, frame_eps, h0, vmax);
  cairo_save(c);
  cairo_rectangle(c, kLeft, kTop, pw, ph);
  cairo_set_source_rgb(c, 0.95, 0.95, 0.95);
  cairo_fill_preserve(c);
  cairo_clip(c);
  cairo_translate(c, kLeft, kTop);
  cairo_scale(c, pw / m.n_frames, ph / m.n_rows);
  cairo_set_source_surface(c, img.get(), 0, 0);
  cairo_pattern_set_filter(cairo_get_source(c), CAIRO_FILTER_NEAREST);
  cairo_paint(c);
  cairo_restore(c);

  // The top plate, y / h0 = 1 - eps.
  cairo_save(c);
  cairo_rectangle(c, kLeft, kTop, pw, ph);
  cairo_clip(c);
  cairo_set_source_rgb(c, 0.2, 0.55, 0.9);
  cairo_set_line_width(c, 1.5);
  cairo_move_to(c, px(eps0), py(1 - eps0));
  cairo_line_to(c, px(eps1), py(1 - eps1));
  cairo_stroke(c);
  cairo_restore(c);

  // Frame, ticks and labels.
  cairo_set_source_rgb(c, 0.2, 0.2, 0.2);
  cairo_set_line_width(c, 1);
  cairo_rectangle(c, kLeft + 0.5, kTop + 0.5, pw, ph);
  cairo_stroke(c);
  for (double t : nice_ticks(eps0, eps1, 8)) {
    cairo_move_to(c, std::round(px(t)) + 0.5, kTop + ph);
    cairo_line_to(c, std::round(px(t)) + 0.5, kTop + ph + 5);
    cairo_stroke(c);
    text(c, tick_text(t), px(t), kTop + ph + 8, 12, 0.5, 0);
  }
  for (double t : nice_ticks(0, top, 6)) {
    cairo_move_to(c, kLeft - 5, std::round(py(t)) + 0.5);
    cairo_line_to(c, kLeft, std::round(py(t)) + 0.5);
    cairo_stroke(c);
    text(c, tick_text(t), kLeft - 8, py(t), 12, 1, 0.5);
  }
  text(c, "imposed strain \u03b5 = Vt / h\u2080", kLeft + pw / 2, kHeight - 8, 13, 0.5, 1);
  text(c, "height y / h\u2080", 18, kTop + ph / 2, 13, 0.5, 0.5, -M_PI / 2);

  // The colour bar.
  const double bx = kLeft + pw + 16, bw = 14;
  for (int i = 0; i < static_cast<int>(ph); ++i) {
    const Rgb col = inferno(1.0 - i / (ph - 1));
    cairo_set_source_rgb(c, col.r / 255.0, col.g / 255.0, col.b / 255.0);
    cairo_rectangle(c, bx, kTop + i, bw, 1);
    cairo_fill(c);
  }
  cairo_set_source_rgb(c, 0.2, 0.2, 0.2);
  cairo_rectangle(c, bx + 0.5, kTop + 0.5, bw, ph);
  cairo_stroke(c);
  for (double t : nice_ticks(0, vmax, 5)) {
    const double y = kTop + ph - t / vmax * ph;
    cairo_move_to(c, bx + bw, std::round(y) + 0.5);
    cairo_line_to(c, bx + bw + 4, std::round(y) + 0.5);
    cairo_stroke(c);
    text(c, tick_text(t), bx + bw + 7, y, 11, 0, 0.5);
  }
  text(c, "log\u2081\u2080(1 + |d\u03b5\u209a/dt| / (V/h\u2080))", bx + bw + 52, kTop + ph / 2, 12, 0.5, 0,
       -M_PI / 2);

  cairo_surface_flush(surface.get());
  if (cairo_surface_write_to_png(surface.get(), path.c_str()) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error("cannot write " + path.string());
  }
}

}  // namespace compaction
