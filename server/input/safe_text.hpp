// Text from a client made safe before it is echoed: into a JSON answer (valid UTF-8), into the
// log (one line, no control characters, bounded), or into an error message (a short
// description of a value instead of the value).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace compaction::server {

// The text with every invalid UTF-8 sequence replaced by U+FFFD.
std::string valid_utf8(std::string_view s);

// One log-safe line: invalid UTF-8 and control characters (newlines, ESC, DEL, C1) written as
// \n, \r, \t or \xNN, backslashes doubled, cut to max_bytes with "..." appended.
std::string log_escape(std::string_view s, std::size_t max_bytes = 200);

// A bounded description of a JSON value for an error message: scalars as short JSON text
// (strings cut to 40 bytes), containers by their kind and size ("an array of 3 values").
std::string describe(const nlohmann::json& v);

// Whether the text holds a control character (C0, DEL or C1) or invalid UTF-8; with
// allow_newlines, newlines and tabs do not count.
bool has_control_characters(std::string_view s, bool allow_newlines = false);

}  // namespace compaction::server
