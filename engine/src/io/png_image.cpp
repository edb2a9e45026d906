// PNG encoding: signature, IHDR, one zlib-compressed IDAT (filter 0 per row), IEND.
#include "png_image.hpp"

#include <zlib.h>

#include <algorithm>
#include <fstream>
#include <stdexcept>
#include <string>

namespace compaction {

void Image::fill_rect(int x0, int y0, int x1, int y1, Rgb c) {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0);
  x1 = std::min(x1, width), y1 = std::min(y1, height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) at(x, y) = c;
}

namespace {

void put_u32(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}

void put_chunk(std::ofstream& f, const char* type, const std::vector<unsigned char>& data) {
  std::vector<unsigned char> buf;
  put_u32(buf, static_cast<std::uint32_t>(data.size()));
  buf.insert(buf.end(), type, type + 4);
  buf.insert(buf.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, buf.data() + 4, static_cast<uInt>(buf.size() - 4));
  put_u32(buf, static_cast<std::uint32_t>(crc));
  f.write(reinterpret_cast<const char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
}

}  // namespace

void write_png(const std::filesystem::path& path, const Image& image) {
  std::vector<unsigned char> raw;
  raw.reserve(static_cast<std::size_t>(image.height) * (1 + 3 * image.width));
  for (int y = 0; y < image.height; ++y) {
    raw.push_back(0);  // filter type: none
    for (int x = 0; x < image.width; ++x) {
      const Rgb& p = image.pixels[static_cast<std::size_t>(y) * image.width + x];
      raw.insert(raw.end(), {p.r, p.g, p.b});
    }
  }
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<unsigned char> packed(packed_size);
  if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 6) !=
      Z_OK) {
    throw std::runtime_error("zlib failed to compress " + path.string());
  }
  packed.resize(packed_size);

  std::vector<unsigned char> ihdr;
  put_u32(ihdr, static_cast<std::uint32_t>(image.width));
  put_u32(ihdr, static_cast<std::uint32_t>(image.height));
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});  // 8 bits, truecolour, deflate, filter 0, no interlace

  std::ofstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  f.write(reinterpret_cast<const char*>(signature), 8);
  put_chunk(f, "IHDR", ihdr);
  put_chunk(f, "IDAT", packed);
  put_chunk(f, "IEND", {});
  if (!f) throw std::runtime_error("error writing " + path.string());
}

}  // namespace compaction
