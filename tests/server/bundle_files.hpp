// Well-formed files of a result bundle for the server's tests, as small as their formats allow:
// an upload is checked file by file (compaction/bundle_check.hpp) before it is stored.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace test_files {

// A float32 .npy of rows x cols, every element the bytes of `fill` (a byte pattern).
inline std::string npy(std::size_t rows, std::size_t cols, char fill = '\x7f') {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(rows) +
                       ", " + std::to_string(cols) + "), }";
  const std::size_t padded = (10 + header.size() + 1 + 63) / 64 * 64;
  header.append(padded - 10 - header.size() - 1, ' ');
  header.push_back('\n');
  std::string out("\x93NUMPY\x01\x00", 8);
  out.push_back(static_cast<char>(header.size() & 0xff));
  out.push_back(static_cast<char>(header.size() >> 8));
  return out + header + std::string(rows * cols * 4, fill);
}

// A PNG's structure: the signature, an IHDR chunk of a 1 x 1 image and an IEND chunk (the
// checksums are not checked, the chunks' lengths are).
inline std::string png() {
  std::string out("\x89PNG\r\n\x1a\n", 8);
  out += std::string("\x00\x00\x00\x0d", 4) + "IHDR" + std::string("\x00\x00\x00\x01\x00\x00\x00\x01\x08\x02\x00\x00\x00", 13) +
         std::string(4, '\0');
  out += std::string(4, '\0') + "IEND" + std::string(4, '\0');
  return out;
}

// frames.csv with a header and `rows` rows of numbers.
inline std::string frames_csv(int rows = 2) {
  std::string out = "eps,sigma_top\n";
  for (int i = 1; i <= rows; ++i) out += std::to_string(0.01 * i) + "," + std::to_string(i) + "\n";
  return out;
}

// movie.bin (schema/movie-format.md) of n particles and `frames` frames, every byte of the
// frames zero.
inline std::string movie(std::uint64_t n, std::uint64_t frames) {
  const std::uint64_t frame_bytes = (8 + 5 * n + 7) / 8 * 8;
  std::string out(96, '\0');
  auto put = [&out](std::size_t at, auto v) { std::memcpy(out.data() + at, &v, sizeof v); };
  out.replace(0, 8, "CSMOVIE1");
  put(8, std::uint32_t{1});
  put(12, std::uint32_t{96});
  put(16, n);
  put(24, frames);
  put(32, frame_bytes);
  put(40, 0.02);
  put(56, 0.5);
  put(72, 1.0);
  put(80, 4.0);
  return out + std::string(frames * frame_bytes, '\0');
}

}  // namespace test_files
