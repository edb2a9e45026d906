// NumPy .npy format 1.0 for little-endian float32 arrays (the big arrays of a bundle).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string_view>
#include <vector>

namespace compaction::npy {

struct Array {
  std::vector<std::size_t> shape;
  std::vector<float> data;  // C order
};

// Writes data (C order, product of shape elements) as '<f4'. Throws std::runtime_error.
void write(const std::filesystem::path& path, const float* data,
           const std::vector<std::size_t>& shape);
// Reads a '<f4' C-order array written by write() (or by numpy.save). Throws std::runtime_error.
Array read(const std::filesystem::path& path);

// An array's layout from the start of its file (the 10-byte preamble and the header): its
// shape, its element count and where the data starts. Throws std::runtime_error for anything
// but a '<f4' C-order array of 1 to 8 dimensions and at most kMaxElements elements (a header
// cannot claim 2^70 elements).
inline constexpr std::size_t kMaxElements = std::size_t{1} << 36;
struct Layout {
  std::vector<std::size_t> shape;
  std::size_t count = 0;
  std::size_t data_offset = 0;
};
Layout parse_header(std::string_view bytes);

}  // namespace compaction::npy
