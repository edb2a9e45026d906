// CSV cells as the exports write them (GET /sweeps/{id}/export?format=csv, GET /jobs?format=csv):
// numbers as JSON writes them; text quoted when it holds a separator, and, as OWASP recommends
// against CSV injection, a text cell that a spreadsheet would read as a formula (starting with
// =, +, -, @, a tab or a carriage return) gets a leading ' and quotes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace compaction::server {

std::string csv_text(std::string_view text);
// The same cells appended to `out` (the long answers build their lines in one buffer): a text,
// a number as JSON writes it, an integer.
void append_csv_text(std::string& out, std::string_view text);
void append_csv_number(std::string& out, double x);
void append_csv_integer(std::string& out, std::int64_t n);
// A JSON value's cell: null empty, a string as csv_text, anything else as its JSON text.
std::string csv_field(const nlohmann::json& v);

}  // namespace compaction::server
