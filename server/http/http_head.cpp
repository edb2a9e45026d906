#include "http/http_head.hpp"

#include <algorithm>
#include <array>

namespace compaction::server {

namespace {

char lower(char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; }

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) { return lower(x) == lower(y); });
}

// tchar of RFC 9110 5.6.2.
bool token_char(char c) {
  static constexpr std::string_view extra = "!#$%&'*+-.^_`|~";
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         extra.find(c) != std::string_view::npos;
}

bool token(std::string_view s) { return !s.empty() && std::all_of(s.begin(), s.end(), token_char); }

// field-vchar, SP or HTAB (RFC 9110 5.5); obs-text (bytes >= 0x80) is allowed.
bool value_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return u == '\t' || (u >= 0x20 && u != 0x7f);
}

// Fields defined as a single value: a second line of one is an error, never merged.
bool singleton(std::string_view name) {
  static constexpr std::array<std::string_view, 10> names = {
      "host",   "content-length", "content-type", "authorization", "origin",
      "expect", "sec-fetch-site", "range",        "cookie",        "if-modified-since"};
  return std::any_of(names.begin(), names.end(), [&](std::string_view n) { return iequals(n, name); });
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  c = lower(c);
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

std::optional<std::string> percent_decoded(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      out += s[i];
      continue;
    }
    if (i + 2 >= s.size()) return std::nullopt;
    const int hi = hex_digit(s[i + 1]), lo = hex_digit(s[i + 2]);
    if (hi < 0 || lo < 0) return std::nullopt;
    const char c = static_cast<char>(hi * 16 + lo);
    if (c == '\0') return std::nullopt;
    out += c;
    i += 2;
  }
  return out;
}

// Whether a comma-separated list field holds `wanted` as one of its elements.
bool list_has(std::string_view list, std::string_view wanted) {
  while (!list.empty()) {
    const auto comma = list.find(',');
    if (iequals(trim(list.substr(0, comma)), wanted)) return true;
    if (comma == std::string_view::npos) break;
    list.remove_prefix(comma + 1);
  }
  return false;
}

HeadError bad(std::string field, std::string message) {
  return {400, std::move(field), std::move(message)};
}

std::variant<RequestHead, HeadError> parse_request_line(std::string_view line, RequestHead& h) {
  const auto sp1 = line.find(' ');
  const auto sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
  if (sp2 == std::string_view::npos || line.find(' ', sp2 + 1) != std::string_view::npos) {
    return bad("request", "the request line must be: METHOD SP /path SP HTTP/1.1");
  }
  const std::string_view method = line.substr(0, sp1);
  const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
  const std::string_view version = line.substr(sp2 + 1);
  if (!token(method)) return bad("request", "the method must be a token");
  if (target.size() > kMaxTargetBytes) {
    return HeadError{414, "request", "the request target is longer than " +
                                         std::to_string(kMaxTargetBytes) + " bytes"};
  }
  if (target.empty() || target.front() != '/') {
    return bad("request", "the request target must be a path starting with '/'");
  }
  for (char c : target) {
    const auto u = static_cast<unsigned char>(c);
    if (u <= 0x20 || u == 0x7f) return bad("request", "the request target holds a control character");
  }
  if (version != "HTTP/1.1" && version != "HTTP/1.0") {
    return bad("request", "the request line must end in HTTP/1.1 or HTTP/1.0");
  }
  const auto path = percent_decoded(target.substr(0, target.find('?')));
  if (!path) return bad("request", "the path holds an invalid or NUL percent escape");
  h.method = method;
  h.target = target;
  h.version = version;
  h.path = *path;
  return h;
}

}  // namespace

const std::string* RequestHead::find(std::string_view name) const {
  for (const auto& [n, v] : fields) {
    if (iequals(n, name)) return &v;
  }
  return nullptr;
}

std::size_t leading_empty_lines(std::string_view bytes) {
  std::size_t i = 0;
  while (bytes.substr(i, 2) == "\r\n") i += 2;
  return i;
}

std::optional<std::size_t> find_head_end(std::string_view bytes, std::size_t from) {
  const std::size_t start = leading_empty_lines(bytes);
  from = std::max(from, start);
  // The end may straddle the previous search's last bytes.
  from = from >= start + 3 ? from - 3 : start;
  const auto at = bytes.find("\r\n\r\n", from);
  if (at == std::string_view::npos) return std::nullopt;
  return at + 4;
}

std::variant<RequestHead, HeadError> parse_request_head(std::string_view head) {
  head.remove_prefix(leading_empty_lines(head));
  RequestHead h;
  std::size_t line_no = 0;
  while (!head.empty()) {
    const auto crlf = head.find("\r\n");
    if (crlf == std::string_view::npos) return bad("request", "every line of the head must end in CRLF");
    const std::string_view line = head.substr(0, crlf);
    head.remove_prefix(crlf + 2);
    if (line.find('\n') != std::string_view::npos || line.find('\r') != std::string_view::npos) {
      return bad("request", "a bare CR or LF inside a line of the head");
    }
    if (line_no++ == 0) {
      auto r = parse_request_line(line, h);
      if (std::holds_alternative<HeadError>(r)) return r;
      continue;
    }
    if (line.empty()) return bad("request", "an empty line inside the head");
    if (line.front() == ' ' || line.front() == '\t') {
      return bad("request", "a header line starts with whitespace (obs-fold is not accepted)");
    }
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return bad("request", "a header line without a colon");
    const std::string_view name = line.substr(0, colon);
    if (!token(name)) {
      return bad("request", "a header name must be a token, with no space before its colon");
    }
    const std::string_view value = trim(line.substr(colon + 1));
    if (!std::all_of(value.begin(), value.end(), value_char)) {
      return bad(std::string(name), "the value holds a control character");
    }
    if (singleton(name) && h.find(name)) {
      return bad(std::string(name), "appears twice; it takes one value");
    }
    if (h.fields.size() >= kMaxHeadFields) {
      return HeadError{431, "request", "more than " + std::to_string(kMaxHeadFields) + " header fields"};
    }
    h.fields.emplace_back(name, value);
  }
  if (line_no == 0) return bad("request", "an empty request");

  if (h.version == "HTTP/1.1" && !h.find("Host")) return bad("Host", "an HTTP/1.1 request needs a Host");
  if (const std::string* cl = h.find("Content-Length")) {
    if (cl->empty() || cl->size() > 18 || cl->find_first_not_of("0123456789") != std::string::npos) {
      return bad("Content-Length", "must be a number of bytes");
    }
    if (h.find("Transfer-Encoding")) {
      return bad("Content-Length", "a request takes Content-Length or Transfer-Encoding, not both");
    }
    h.content_length = std::stoull(*cl);
  }
  if (const std::string* expect = h.find("Expect")) {
    if (!iequals(*expect, "100-continue")) {
      return HeadError{417, "Expect", "the only expectation this server meets is 100-continue"};
    }
    h.expect_continue = true;
  }
  // Connection is a list: it may come in several lines.
  bool close = false, keep_alive = false;
  for (const auto& [name, value] : h.fields) {
    if (!iequals(name, "Connection")) continue;
    close = close || list_has(value, "close");
    keep_alive = keep_alive || list_has(value, "keep-alive");
  }
  h.keep_alive = !close && (h.version == "HTTP/1.1" || keep_alive);
  return h;
}

}  // namespace compaction::server
