// JSON text from a client, parsed with bounds: at most max_json_depth levels of nesting (checked
// by a scan before the parser runs, so no recursive code ever sees a deeper value), valid UTF-8
// (nlohmann's parser refuses anything else) and no NaN or infinite numbers.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace compaction::server {

// Deeper than any document of the API (a sweep request is 4 levels deep, a summary 5).
constexpr int max_json_depth = 64;

// The deepest nesting of arrays and objects in the text, counting outside strings; stops
// counting at limit + 1.
int json_nesting_depth(std::string_view text, int limit = max_json_depth);

// The value of an integer JSON number as a signed 64-bit integer; nothing for any other value,
// and for an integer beyond the signed range (nlohmann keeps 2^63 and above unsigned, where
// get<std::int64_t>() would wrap to a negative number).
std::optional<std::int64_t> as_int64(const nlohmann::json& v);

// Parses text or throws ApiError(status, field, reason): "malformed JSON" or "nested deeper
// than 64 levels".
nlohmann::json parse_client_json(std::string_view text, const std::string& field, int status = 400);

}  // namespace compaction::server
