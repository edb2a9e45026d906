// Writes movie.bin frame by frame (schema/movie-format.md).
#include "movie_recorder.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "compaction/movie.hpp"

namespace compaction {

namespace {

template <typename T>
void put(unsigned char* at, T v) {
  std::memcpy(at, &v, sizeof v);  // little-endian hosts (x86-64, arm64)
}

// A coordinate in [0, extent] as 0 .. 65535 (scale = 65535 / extent), clamped.
std::uint16_t quantise(double v, double scale) {
  const double q = std::round(v * scale);
  return static_cast<std::uint16_t>(q >= 0.0 ? (q <= 65535.0 ? q : 65535.0) : 0.0);  // NaN: 0
}

}  // namespace

MovieRecorder::MovieRecorder(std::string path, const SceneParams& p, const State& s)
    : path_(std::move(path)),
      every_(p.movie_d_eps),
      width_(s.setup.width),
      height_(s.setup.h0),
      flags_(s.grid.periodic_x ? movie::kPeriodicX : 0u),
      n_(s.particles.n),
      frame_(movie::frame_bytes(s.particles.n), 0) {}

void MovieRecorder::resume(std::int64_t frames_written) { open(frames_written); }

void MovieRecorder::open(std::int64_t frames_written) {
  if (file_) std::fclose(file_), file_ = nullptr;
  unsigned char header[movie::kHeaderBytes] = {};
  std::memcpy(header, movie::kMagic, sizeof movie::kMagic);
  put(header + 8, movie::kVersion);
  put(header + 12, static_cast<std::uint32_t>(movie::kHeaderBytes));
  put(header + 16, static_cast<std::uint64_t>(n_));
  put(header + 24, static_cast<std::uint64_t>(frames_written));
  put(header + 32, static_cast<std::uint64_t>(frame_.size()));
  put(header + 40, every_);
  put(header + 48, 0.0);  // x_lo
  put(header + 56, width_);
  put(header + 64, 0.0);  // y_lo
  put(header + 72, height_);
  put(header + 80, movie::kRateLog10Max);
  put(header + 88, flags_);
  if (frames_written <= 0) {
    file_ = std::fopen(path_.c_str(), "wb");
    if (!file_) fail("cannot create");
  } else {
    file_ = std::fopen(path_.c_str(), "r+b");
    if (!file_) fail("cannot reopen");
    unsigned char old[movie::kHeaderBytes];
    const long keep = static_cast<long>(movie::kHeaderBytes + frames_written * frame_.size());
    // the same scene's file: the header but for the frame count, and the frames kept
    const bool same = std::fread(old, 1, sizeof old, file_) == sizeof old &&
                      std::memcmp(old, header, 24) == 0 &&
                      std::memcmp(old + 32, header + 32, sizeof old - 32) == 0 &&
                      std::fseek(file_, 0, SEEK_END) == 0 && std::ftell(file_) >= keep;
    if (!same) {
      std::fclose(file_);
      file_ = nullptr;
      throw std::runtime_error(path_ + ": not this scene's movie, or shorter than " +
                               std::to_string(frames_written) + " frames");
    }
    if (::ftruncate(::fileno(file_), keep) != 0) fail("cannot truncate");
  }
  frames_ = std::max<std::int64_t>(0, frames_written);
  if (std::fseek(file_, 0, SEEK_SET) != 0 ||
      std::fwrite(header, 1, sizeof header, file_) != sizeof header ||
      std::fseek(file_, 0, SEEK_END) != 0 || std::fflush(file_) != 0) {
    fail("cannot write the header of");
  }
}

MovieRecorder::~MovieRecorder() {
  if (file_) std::fclose(file_);
}

void MovieRecorder::fail(const char* what) const {
  throw std::runtime_error(std::string(what) + " " + path_ + ": " + std::strerror(errno));
}

void MovieRecorder::record_if_due(const Particles& P, double eps_end, double d_eps) {
  if (eps_end < (frames_ + 1) * every_ - 1e-9) return;
  if (!file_) open(0);
  unsigned char* f = frame_.data();
  put(f, eps_end);
  unsigned char* xs = f + 8;
  unsigned char* ys = xs + 2 * n_;
  unsigned char* rates = ys + 2 * n_;
  const double inv_d_eps = 1.0 / d_eps;
  const double x_scale = 65535.0 / width_, y_scale = 65535.0 / height_;
  for (std::size_t k = 0; k < n_; ++k) {
    put(xs + 2 * k, quantise(P.x[k], x_scale));
    put(ys + 2 * k, quantise(P.y[k], y_scale));
    rates[k] = movie::rate_level(P.dep[k] * inv_d_eps);
  }
  if (std::fwrite(frame_.data(), 1, frame_.size(), file_) != frame_.size()) fail("cannot write");
  ++frames_;  // an output frame passes at most one multiple: validate() keeps movie_d_eps >= d_eps
  // The file is whole after each frame: its count follows the frame that made it true.
  const std::uint64_t count = static_cast<std::uint64_t>(frames_);
  if (std::fseek(file_, 24, SEEK_SET) != 0 || std::fwrite(&count, sizeof count, 1, file_) != 1 ||
      std::fseek(file_, 0, SEEK_END) != 0 || std::fflush(file_) != 0) {
    fail("cannot write");
  }
}

}  // namespace compaction
