#include "input/safe_text.hpp"

#include <cstdio>

namespace compaction::server {

namespace {

// Length of the valid UTF-8 sequence starting at s[i] (1-4), or 0 when it is invalid
// (overlong forms, surrogates and code points above U+10FFFF are invalid, RFC 3629).
std::size_t utf8_sequence(std::string_view s, std::size_t i) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char c = b(i);
  if (c < 0x80) return 1;
  std::size_t n = 0;
  unsigned lo = 0x80, hi = 0xBF;  // the allowed range of the second byte
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  if (b(i + 1) < lo || b(i + 1) > hi) return 0;
  for (std::size_t k = 2; k < n; ++k) {
    if (b(i + k) < 0x80 || b(i + k) > 0xBF) return 0;
  }
  return n;
}

// The code point of a valid sequence of length n at s[i].
unsigned code_point(std::string_view s, std::size_t i, std::size_t n) {
  const auto b = [&](std::size_t k) { return static_cast<unsigned>(static_cast<unsigned char>(s[k])); };
  if (n == 1) return b(i);
  unsigned cp = b(i) & (0x7Fu >> n);
  for (std::size_t k = 1; k < n; ++k) cp = (cp << 6) | (b(i + k) & 0x3Fu);
  return cp;
}

bool is_control(unsigned cp) { return cp < 0x20 || cp == 0x7F || (cp >= 0x80 && cp <= 0x9F); }

}  // namespace

std::string valid_utf8(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_sequence(s, i);
    if (n == 0) {
      out += "\xEF\xBF\xBD";  // U+FFFD
      ++i;
    } else {
      out.append(s.substr(i, n));
      i += n;
    }
  }
  return out;
}

std::string log_escape(std::string_view s, std::size_t max_bytes) {
  std::string out;
  char hex[8];
  for (std::size_t i = 0; i < s.size();) {
    if (out.size() >= max_bytes) {
      out += "...";
      break;
    }
    const std::size_t n = utf8_sequence(s, i);
    if (n == 0) {
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(s[i]));
      out += hex;
      ++i;
      continue;
    }
    const unsigned cp = code_point(s, i, n);
    if (cp == '\\') {
      out += "\\\\";
    } else if (cp == '\n') {
      out += "\\n";
    } else if (cp == '\r') {
      out += "\\r";
    } else if (cp == '\t') {
      out += "\\t";
    } else if (is_control(cp)) {
      std::snprintf(hex, sizeof hex, "\\x%02x", cp);
      out += hex;
    } else {
      out.append(s.substr(i, n));
    }
    i += n;
  }
  return out;
}

std::string describe(const nlohmann::json& v) {
  using nlohmann::json;
  switch (v.type()) {
    case json::value_t::object: return "an object of " + std::to_string(v.size()) + " keys";
    case json::value_t::array: return "an array of " + std::to_string(v.size()) + " values";
    case json::value_t::string: {
      const auto& s = v.get_ref<const std::string&>();
      const json cut = s.size() > 40 ? json(valid_utf8(s.substr(0, 40)) + "...") : json(s);
      return cut.dump(-1, ' ', false, json::error_handler_t::replace);
    }
    case json::value_t::discarded: return "nothing";
    default: return v.dump();  // null, boolean, number: short by nature
  }
}

bool has_control_characters(std::string_view s, bool allow_newlines) {
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = utf8_sequence(s, i);
    if (n == 0) return true;  // invalid UTF-8 counts as unprintable
    const unsigned cp = code_point(s, i, n);
    if (is_control(cp) && !(allow_newlines && (cp == '\n' || cp == '\t' || cp == '\r'))) {
      return true;
    }
    i += n;
  }
  return false;
}

}  // namespace compaction::server
