// A minimal RGB image and its PNG encoding (zlib-compressed, 8-bit truecolour).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace compaction {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
};

struct Image {
  int width = 0, height = 0;
  std::vector<Rgb> pixels;  // row-major, row 0 at the top
  Image(int w, int h, Rgb fill = {255, 255, 255})
      : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}
  Rgb& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  void fill_rect(int x0, int y0, int x1, int y1, Rgb c);  // [x0, x1) x [y0, y1), clipped
};

// Throws std::runtime_error when the file cannot be written.
void write_png(const std::filesystem::path& path, const Image& image);

}  // namespace compaction
