// The sizes and rate levels of movie.bin, and reading it back (schema/movie-format.md).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "compaction/movie.hpp"

namespace compaction::movie {

namespace fs = std::filesystem;

std::size_t frame_bytes(std::size_t n_particles) {
  const std::size_t raw = 8 + 5 * n_particles;
  return (raw + 7) / 8 * 8;
}

std::size_t frame_count(const SceneParams& p) {
  if (!(p.movie_d_eps > 0.0)) return 0;
  // the tolerance of the recorder: a multiple reached up to round-off counts
  return static_cast<std::size_t>(std::floor(p.eps_final() / p.movie_d_eps + 1e-9));
}

std::uint8_t rate_level(double rate) {
  if (!(rate > 0.0)) return 0;  // also NaN
  const double t = std::log10(1.0 + rate) / kRateLog10Max;
  return static_cast<std::uint8_t>(std::lround(std::min(1.0, t) * 255.0));
}

double rate_of_level(std::uint8_t level) {
  return std::pow(10.0, level / 255.0 * kRateLog10Max) - 1.0;
}

namespace {

template <typename T>
T at(std::string_view bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof v);  // little-endian hosts (x86-64, arm64)
  return v;
}

std::string read_bytes(const fs::path& path, std::size_t max_bytes) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  std::string bytes(max_bytes, '\0');
  f.read(bytes.data(), static_cast<std::streamsize>(max_bytes));
  bytes.resize(static_cast<std::size_t>(f.gcount()));
  return bytes;
}

}  // namespace

Header parse_header(std::string_view bytes, std::uintmax_t file_size) {
  auto bad = [](const std::string& why) { return std::runtime_error(why); };
  if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw bad("not a movie (magic CSMOVIE1 and a 96-byte header expected)");
  }
  if (at<std::uint32_t>(bytes, 8) != kVersion) throw bad("unknown version");
  if (at<std::uint32_t>(bytes, 12) != kHeaderBytes) throw bad("unexpected header size");
  Header h;
  h.n_particles = at<std::uint64_t>(bytes, 16);
  h.n_frames = at<std::uint64_t>(bytes, 24);
  const std::uint64_t fb = at<std::uint64_t>(bytes, 32);
  h.movie_d_eps = at<double>(bytes, 40);
  h.x_lo = at<double>(bytes, 48), h.x_hi = at<double>(bytes, 56);
  h.y_lo = at<double>(bytes, 64), h.y_hi = at<double>(bytes, 72);
  h.rate_log10_max = at<double>(bytes, 80);
  h.flags = at<std::uint32_t>(bytes, 88);
  if (h.n_particles > (std::uint64_t{1} << 40) || fb != frame_bytes(h.n_particles)) {
    throw bad("frame size does not match the particle count");
  }
  if (h.n_frames > (file_size - kHeaderBytes) / fb) throw bad("shorter than its frame count");
  return h;
}

Header read_header(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw std::runtime_error("cannot read " + path.string());
  try {
    return parse_header(read_bytes(path, kHeaderBytes), size);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
}

Movie read(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw std::runtime_error("cannot read " + path.string());
  const std::string bytes = read_bytes(path, size);
  Movie m;
  try {
    m.header = parse_header(bytes, bytes.size());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  const Header& h = m.header;
  const std::size_t n = h.n_particles, fb = frame_bytes(n);
  const double sx = (h.x_hi - h.x_lo) / 65535.0, sy = (h.y_hi - h.y_lo) / 65535.0;
  for (std::uint64_t k = 0; k < h.n_frames; ++k) {
    const std::size_t o = kHeaderBytes + k * fb;
    Frame fr;
    fr.eps = at<double>(bytes, o);
    fr.x.resize(n), fr.y.resize(n), fr.level.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      fr.x[i] = static_cast<float>(h.x_lo + sx * at<std::uint16_t>(bytes, o + 8 + 2 * i));
      fr.y[i] = static_cast<float>(h.y_lo + sy * at<std::uint16_t>(bytes, o + 8 + 2 * (n + i)));
      fr.level[i] = static_cast<std::uint8_t>(bytes[o + 8 + 4 * n + i]);
    }
    m.frames.push_back(std::move(fr));
  }
  return m;
}

}  // namespace compaction::movie
