#include "json_input.hpp"

#include "api_error.hpp"

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
