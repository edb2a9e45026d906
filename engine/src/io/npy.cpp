// NumPy .npy format 1.0: magic, version, header length, a Python-dict header padded to a
// multiple of 64 bytes, then the raw data (https://numpy.org/neps/nep-0001-npy-format.html).
#include "npy.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <string_view>

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

Layout parse_header(std::string_view bytes) {
  constexpr std::size_t preamble = 10;
  if (bytes.size() < preamble || std::memcmp(bytes.data(), kMagic, 6) != 0 ||
      static_cast<unsigned char>(bytes[6]) != 1) {
    throw std::runtime_error("not an .npy file of format 1.x");
  }
  const std::size_t length = static_cast<unsigned char>(bytes[8]) |
                             (static_cast<std::size_t>(static_cast<unsigned char>(bytes[9])) << 8);
  if (bytes.size() < preamble + length) throw std::runtime_error("truncated header");
  const std::string_view header = bytes.substr(preamble, length);
  if (header.find("'descr': '<f4'") == std::string_view::npos ||
      header.find("'fortran_order': False") == std::string_view::npos) {
    throw std::runtime_error("expected a C-order '<f4' array");
  }
  // The shape is a tuple of decimal integers: "'shape': (3, 4), " or "'shape': (3,), ".
  constexpr std::string_view key = "'shape': (";
  const std::size_t open = header.find(key);
  const std::size_t close = open == std::string_view::npos ? open : header.find(')', open);
  if (close == std::string_view::npos) throw std::runtime_error("no shape in the header");
  Layout l;
  l.data_offset = preamble + length;
  l.count = 1;
  for (std::size_t i = open + key.size(); i < close;) {
    const char c = header[i];
    if (c == ',' || c == ' ') {
      ++i;
      continue;
    }
    if (c < '0' || c > '9') throw std::runtime_error("the shape holds something else than sizes");
    std::size_t value = 0;
    for (; i < close && header[i] >= '0' && header[i] <= '9'; ++i) {
      if (value > kMaxElements) throw std::runtime_error("a size of the shape is too large");
      value = value * 10 + static_cast<std::size_t>(header[i] - '0');
    }
    if (value > kMaxElements || (value > 0 && l.count > kMaxElements / value)) {
      throw std::runtime_error("more than " + std::to_string(kMaxElements) + " elements");
    }
    l.shape.push_back(value);
    l.count *= value;
  }
  if (l.shape.empty() || l.shape.size() > 8) throw std::runtime_error("expected 1 to 8 dimensions");
  return l;
}

Array read(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::string head(10, '\0');
  in.read(head.data(), 10);
  Layout l;
  try {
    if (!in) throw std::runtime_error("not an .npy file of format 1.x");
    const std::size_t length = static_cast<unsigned char>(head[8]) |
                               (static_cast<std::size_t>(static_cast<unsigned char>(head[9])) << 8);
    head.resize(10 + length);
    in.read(head.data() + 10, static_cast<std::streamsize>(length));
    l = parse_header(head);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
  Array a;
  a.shape = l.shape;
  a.data.resize(l.count);
  in.read(reinterpret_cast<char*>(a.data.data()), static_cast<std::streamsize>(l.count * 4));
  if (!in) throw std::runtime_error(path.string() + ": truncated data");
  return a;
}

}  // namespace compaction::npy
