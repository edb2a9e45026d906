#include "compaction/bundle_check.hpp"

#include <charconv>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "compaction/movie.hpp"
#include "npy.hpp"

namespace compaction {

namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::optional<std::string> npy_problem(std::string_view bytes) {
  try {
    const npy::Layout l = npy::parse_header(bytes);
    if (bytes.size() != l.data_offset + l.count * 4) {
      return "holds " + std::to_string(bytes.size() - std::min(bytes.size(), l.data_offset)) +
             " bytes of data, its shape says " + std::to_string(l.count * 4);
    }
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return std::nullopt;
}

// The length of the UTF-8 sequence starting at s[i], or 0 when it is invalid.
std::size_t utf8_length(std::string_view s, std::size_t i) {
  const auto c = static_cast<unsigned char>(s[i]);
  if (c < 0x80) return 1;
  std::size_t n = c >= 0xf0 && c <= 0xf4 ? 4 : c >= 0xe0 ? 3 : c >= 0xc2 && c < 0xe0 ? 2 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) return 0;
  }
  return n;
}

bool number(std::string_view field) {
  if (field == "nan" || field == "inf" || field == "-inf" || field == "-nan") return true;
  double v = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  return ec == std::errc() && end == field.data() + field.size();
}

std::optional<std::string> csv_problem(std::string_view bytes) {
  for (std::size_t i = 0; i < bytes.size();) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if (c < 0x20 && c != '\n' && c != '\r') {
      return "holds a control character at byte " + std::to_string(i);
    }
    const std::size_t n = utf8_length(bytes, i);
    if (n == 0) return "is not UTF-8 at byte " + std::to_string(i);
    i += n;
  }
  std::size_t fields = 0;
  std::size_t line_no = 0;
  for (std::size_t start = 0; start < bytes.size();) {
    std::size_t end = bytes.find('\n', start);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(start, end - start);
    start = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++line_no;
    if (line.empty()) {
      if (start >= bytes.size()) break;  // the file's final line end
      return "line " + std::to_string(line_no) + " is empty";
    }
    std::size_t count = 1;
    for (std::size_t from = 0; (from = line.find(',', from)) != std::string_view::npos; ++from) ++count;
    if (line_no == 1) {
      fields = count;
      continue;
    }
    if (count != fields) {
      return "line " + std::to_string(line_no) + " has " + std::to_string(count) +
             " fields, the header " + std::to_string(fields);
    }
    for (std::size_t from = 0; from <= line.size();) {
      std::size_t comma = line.find(',', from);
      if (comma == std::string_view::npos) comma = line.size();
      if (!number(line.substr(from, comma - from))) {
        return "line " + std::to_string(line_no) + " holds a field that is not a number";
      }
      from = comma + 1;
    }
  }
  if (line_no == 0) return "is empty";
  return std::nullopt;
}

std::uint32_t big_endian(std::string_view b, std::size_t at) {
  return (std::uint32_t{static_cast<unsigned char>(b[at])} << 24) |
         (std::uint32_t{static_cast<unsigned char>(b[at + 1])} << 16) |
         (std::uint32_t{static_cast<unsigned char>(b[at + 2])} << 8) |
         std::uint32_t{static_cast<unsigned char>(b[at + 3])};
}

std::optional<std::string> png_problem(std::string_view bytes) {
  static constexpr char signature[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() < 8 || std::memcmp(bytes.data(), signature, 8) != 0) return "is not a PNG image";
  std::size_t at = 8;
  bool first = true;
  while (at + 12 <= bytes.size()) {
    const std::uint32_t length = big_endian(bytes, at);
    const std::string_view type = bytes.substr(at + 4, 4);
    if (length > bytes.size() - at - 12) return "a chunk runs past the end of the file";
    if (first && type != "IHDR") return "does not start with an IHDR chunk";
    first = false;
    at += 12 + length;
    if (type == "IEND") {
      return at == bytes.size() ? std::nullopt
                                : std::optional<std::string>("holds bytes after its IEND chunk");
    }
  }
  return "ends without an IEND chunk";
}

std::optional<std::string> movie_problem(std::string_view bytes) {
  try {
    const movie::Header h = movie::parse_header(bytes, bytes.size());
    if (bytes.size() != movie::kHeaderBytes + h.n_frames * movie::frame_bytes(h.n_particles)) {
      return "its size is not its header and whole frames";
    }
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return std::nullopt;
}

}  // namespace

std::optional<std::string> bundle_file_problem(const std::string& name, std::string_view bytes) {
  if (ends_with(name, ".npy")) return npy_problem(bytes);
  if (ends_with(name, ".csv")) return csv_problem(bytes);
  if (ends_with(name, ".png")) return png_problem(bytes);
  if (ends_with(name, ".bin")) return movie_problem(bytes);
  if (ends_with(name, ".json")) {
    if (nlohmann::json::accept(bytes)) return std::nullopt;
    return "is not one JSON document";
  }
  return "is not a file of a result bundle";
}

}  // namespace compaction
