// Base64 (RFC 4648, standard alphabet, '=' padding, no line breaks): artifacts' bytes inside a
// JSON export file (schema/sweep-export.md).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace compaction::server {

std::string base64_encode(std::string_view bytes);
// nullopt unless the text is canonical base64 (length a multiple of 4, only the alphabet, at
// most two '=' at the end).
std::optional<std::string> base64_decode(std::string_view text);

}  // namespace compaction::server
