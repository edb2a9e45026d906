// NumPy .npy format 1.0: magic, version, header length, a Python-dict header padded to a
// multiple of 64 bytes, then the raw data (https://numpy.org/neps/nep-0001-npy-format.html).
#include "npy.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>

static_assert(sizeof(float) == 4, "float32 expected");

namespace compaction::npy {

namespace {
constexpr char kMagic[] = "\x93NUMPY";
}

void write(const std::filesystem::path& path, const float* data,
           const std::vector<std::size_t>& shape) {
  std::string dims;
  std::size_t count = 1;
  for (std::size_t d : shape) {
    dims += std::to_string(d) + ", ";
    count *= d;
  }
  if (shape.size() > 1) dims.resize(dims.size() - 2);  // "(3,)" for 1-D, "(3, 4)" otherwise
  else if (!shape.empty()) dims.resize(dims.size() - 1);
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  const std::size_t preamble = 10;  // magic (6) + version (2) + header length (2)
  const std::size_t padded = (preamble + header.size() + 1 + 63) / 64 * 64;
  header.append(padded - preamble - header.size() - 1, ' ');
  header.push_back('\n');

  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  out.write(kMagic, 6);
  const unsigned char version[2] = {1, 0};
  out.write(reinterpret_cast<const char*>(version), 2);
  const std::uint16_t len = static_cast<std::uint16_t>(header.size());
  const unsigned char len_le[2] = {static_cast<unsigned char>(len & 0xff),
                                   static_cast<unsigned char>(len >> 8)};
  out.write(reinterpret_cast<const char*>(len_le), 2);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(count * 4));
  if (!out) throw std::runtime_error("error writing " + path.string());
}

Array read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  char magic[6];
  unsigned char version[2], len_le[2];
  in.read(magic, 6);
  in.read(reinterpret_cast<char*>(version), 2);
  in.read(reinterpret_cast<char*>(len_le), 2);
  if (!in || std::memcmp(magic, kMagic, 6) != 0 || version[0] != 1) {
    throw std::runtime_error(path.string() + ": not an .npy file of format 1.x");
  }
  std::string header(static_cast<std::size_t>(len_le[0] | (len_le[1] << 8)), '\0');
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  if (header.find("'<f4'") == std::string::npos ||
      header.find("'fortran_order': False") == std::string::npos) {
    throw std::runtime_error(path.string() + ": expected a C-order '<f4' array");
  }
  // The shape is a tuple of decimal integers: "'shape': (3, 4), " or "'shape': (3,), ".
  const std::string key = "'shape': (";
  const std::size_t open = header.find(key), close = header.find(')', open);
  if (open == std::string::npos || close == std::string::npos) {
    throw std::runtime_error(path.string() + ": no shape in header");
  }
  Array a;
  std::size_t count = 1;
  for (std::size_t i = open + key.size(); i < close;) {
    if (header[i] < '0' || header[i] > '9') {
      ++i;
      continue;
    }
    std::size_t value = 0;
    for (; i < close && header[i] >= '0' && header[i] <= '9'; ++i) value = value * 10 + (header[i] - '0');
    a.shape.push_back(value);
    count *= value;
  }
  a.data.resize(count);
  in.read(reinterpret_cast<char*>(a.data.data()), static_cast<std::streamsize>(count * 4));
  if (!in) throw std::runtime_error(path.string() + ": truncated data");
  return a;
}

}  // namespace compaction::npy
