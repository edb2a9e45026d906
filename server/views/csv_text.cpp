#include "views/csv_text.hpp"

#include <charconv>
#include <cmath>

namespace compaction::server {

namespace {

bool needs_quotes(std::string_view s) { return s.find_first_of(",\"\n\r") != std::string_view::npos; }

// `s` in quotes (`prefix` first inside them), its quotes doubled.
void append_quoted(std::string& out, std::string_view s, std::string_view prefix = "") {
  out += '"';
  out += prefix;
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
}

}  // namespace

void append_csv_text(std::string& out, std::string_view text) {
  const bool formula = !text.empty() && std::string_view("=+-@\t\r").find(text[0]) != std::string_view::npos;
  if (formula) return append_quoted(out, text, "'");
  if (needs_quotes(text)) return append_quoted(out, text);
  out += text;
}

void append_csv_number(std::string& out, double x) {
  if (!std::isfinite(x)) {
    out += "null";  // as nlohmann::json writes a number that is not finite
    return;
  }
  char buf[32];
  char* end = nlohmann::detail::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, end);
}

void append_csv_integer(std::string& out, std::int64_t n) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, n);
  out.append(buf, r.ptr);
}

std::string csv_text(std::string_view text) {
  std::string s;
  append_csv_text(s, text);
  return s;
}

std::string csv_field(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return csv_text(v.get<std::string>());
  const std::string text = v.dump();
  if (!needs_quotes(text)) return text;
  std::string s;
  append_quoted(s, text);
  return s;
}

}  // namespace compaction::server
