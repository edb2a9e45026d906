#include "input/json_input.hpp"

#include <limits>

#include "input/api_error.hpp"

namespace compaction::server {

int json_nesting_depth(std::string_view text, int limit) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > deepest && (deepest = depth) > limit) return deepest;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

std::optional<std::int64_t> as_int64(const nlohmann::json& v) {
  if (v.is_number_unsigned()) {
    const auto u = v.get<std::uint64_t>();
    if (u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) return std::nullopt;
    return static_cast<std::int64_t>(u);
  }
  if (v.is_number_integer()) return v.get<std::int64_t>();
  return std::nullopt;
}

nlohmann::json parse_client_json(std::string_view text, const std::string& field, int status) {
  if (json_nesting_depth(text) > max_json_depth) {
    throw ApiError(status, field,
                   "malformed JSON: nested deeper than " + std::to_string(max_json_depth) +
                       " levels");
  }
  nlohmann::json v = nlohmann::json::parse(text, nullptr, false);
  if (v.is_discarded()) throw ApiError(status, field, "malformed JSON");
  return v;
}

}  // namespace compaction::server
