// CSV cells as the exports write them (GET /sweeps/{id}/export?format=csv, GET /jobs?format=csv):
// numbers as JSON writes them; text quoted when it holds a separator, and, as OWASP recommends
// against CSV injection, a text cell that a spreadsheet would read as a formula (starting with
// =, +, -, @, a tab or a carriage return) gets a leading ' and quotes.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace compaction::server {

std::string csv_text(std::string_view text);
// A JSON value's cell: null empty, a string as csv_text, anything else as its JSON text.
std::string csv_field(const nlohmann::json& v);

}  // namespace compaction::server
