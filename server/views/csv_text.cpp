#include "views/csv_text.hpp"

namespace compaction::server {

namespace {

// The cell quoted (its quotes doubled) when `always` or when it holds a separator.
std::string quoted(std::string s, bool always) {
  if (!always && s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

std::string csv_text(std::string_view text) {
  const bool formula = !text.empty() && std::string_view("=+-@\t\r").find(text[0]) != std::string_view::npos;
  std::string s = formula ? "'" : "";
  s += text;
  return quoted(std::move(s), formula);
}

std::string csv_field(const nlohmann::json& v) {
  if (v.is_null()) return "";
  return v.is_string() ? csv_text(v.get<std::string>()) : quoted(v.dump(), false);
}

}  // namespace compaction::server
