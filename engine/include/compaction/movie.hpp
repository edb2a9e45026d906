// The movie of a run: the particles (positions and plastic strain rate, as the snapshots draw
// them) at every movie_d_eps of imposed strain, in one compact binary file of the bundle,
// movie.bin (schema/movie-format.md). Positions are quantised to 16 bits over the specimen's
// box, the rate to 8 bits on log10(1 + rate) over [0, kRateLog10Max]; every frame has the same
// size, so frame k starts at kHeaderBytes + k * frame_bytes(n).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "compaction/params.hpp"

namespace compaction::movie {

inline constexpr char kFileName[] = "movie.bin";
inline constexpr char kMagic[8] = {'C', 'S', 'M', 'O', 'V', 'I', 'E', '1'};
inline constexpr std::uint32_t kVersion = 1;
inline constexpr std::size_t kHeaderBytes = 96;
// Rates / (V / h0) up to 10^4 - 1 keep their own level; faster ones are stored as that. The
// paper's bands stay below it at every resolution the presets give (docs/dashboard.md).
inline constexpr double kRateLog10Max = 4.0;
inline constexpr std::uint32_t kPeriodicX = 1;  // header flag: x wraps (pseudo-1D)

// Bytes of one frame of n particles: the strain (float64), x and y (uint16 each), the rate
// (uint8), zero padding to a multiple of 8.
std::size_t frame_bytes(std::size_t n_particles);
// Frames a run of p writes when it reaches its final strain: one at each multiple of
// p.movie_d_eps up to eps_final (0 when the movie is off).
std::size_t frame_count(const SceneParams& p);

// The 8-bit level of a rate / (V / h0), and back (the level's centre).
std::uint8_t rate_level(double rate);
double rate_of_level(std::uint8_t level);

// The header of a movie file.
struct Header {
  std::uint64_t n_particles = 0;
  std::uint64_t n_frames = 0;  // whole frames in the file
  double movie_d_eps = 0.0;
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;  // the box of the quantised positions [m]
  double rate_log10_max = kRateLog10Max;
  std::uint32_t flags = 0;
};
// Throws std::runtime_error naming the file when it is missing, malformed or shorter than its
// frame count.
Header read_header(const std::filesystem::path& path);
// The header from a file's first bytes (at least kHeaderBytes), checked against the file's
// size; throws std::runtime_error saying what is wrong.
Header parse_header(std::string_view bytes, std::uintmax_t file_size);

// A movie read back: positions in metres, rates as their levels (rate_of_level decodes them).
struct Frame {
  double eps = 0.0;  // imposed strain of the frame                               [-]
  std::vector<float> x, y;
  std::vector<std::uint8_t> level;  // rate level, 0 .. 255
};
struct Movie {
  Header header;
  std::vector<Frame> frames;
};
// Throws std::runtime_error naming the file when it is missing or malformed.
Movie read(const std::filesystem::path& path);

}  // namespace compaction::movie
