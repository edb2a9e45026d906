#include "compaction/text_numbers.hpp"

#include <charconv>
#include <climits>
#include <cmath>

namespace compaction {

bool parse_finite_real(std::string_view text, double& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return !text.empty() && ec == std::errc() && ptr == end && std::isfinite(out);
}

bool parse_int(std::string_view text, long long& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return !text.empty() && ec == std::errc() && ptr == end;
}

bool parse_int(std::string_view text, int& out) {
  long long v = 0;
  if (!parse_int(text, v) || v < INT_MIN || v > INT_MAX) return false;
  out = static_cast<int>(v);
  return true;
}

}  // namespace compaction
