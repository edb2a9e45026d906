// NumPy .npy format 1.0 for little-endian float32 arrays (the big arrays of a bundle).
#pragma once

#include <cstddef>
#include <filesystem>
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

}  // namespace compaction::npy
