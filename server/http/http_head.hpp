// The head of an HTTP/1.x request (its request line and header fields), read strictly as RFC
// 9112 asks of a server, before any handler sees it:
//  - request-line: method SP origin-form SP HTTP/1.0 or HTTP/1.1, each line ending in CRLF
//    (a bare LF, a control character or a space inside the target, another version: 400);
//  - field lines: "name: value" with a token for the name and no space before the colon; a
//    line without a colon, a line that starts with whitespace (obs-fold, RFC 9112 5.2) or a
//    value holding a control character is 400;
//  - an HTTP/1.1 request needs exactly one Host (RFC 9112 3.2); a field that may appear only
//    once (Host, Content-Length, Content-Type, Authorization, Origin, ...) appearing twice is
//    400 (RFC 9110 5.3); Content-Length is digits only, and never beside Transfer-Encoding
//    (RFC 9112 6.3: the two together are how requests are smuggled);
//  - the path (the target before '?') is percent-decoded and must not hold NUL or invalid
//    escapes; at most max_fields fields (431).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace compaction::server {

struct RequestHead {
  std::string method, target, version;  // version: "HTTP/1.0" or "HTTP/1.1"
  std::string path;                     // the target's path, percent-decoded
  std::vector<std::pair<std::string, std::string>> fields;  // as sent, values trimmed
  std::optional<std::size_t> content_length;
  bool expect_continue = false;         // Expect: 100-continue
  bool keep_alive = true;               // the connection may carry another request after this

  // The value of a field by its name (case-insensitive), or nullptr.
  const std::string* find(std::string_view name) const;
};

struct HeadError {
  int status;           // 400, 414, 417 or 431
  std::string field;    // the part at fault: "request", "Host", "Content-Length", ...
  std::string message;
};

inline constexpr std::size_t kMaxHeadFields = 100;
inline constexpr std::size_t kMaxTargetBytes = 8 << 10;

// `head` is the request line and the field lines, each ending in CRLF, without the empty line
// that ends the head.
std::variant<RequestHead, HeadError> parse_request_head(std::string_view head);

// The index just past the empty line that ends a head in `bytes` (leading empty lines, which
// RFC 9112 2.2 lets a server ignore, are part of the head), searching from `from`; nullopt
// while it has not arrived.
std::optional<std::size_t> find_head_end(std::string_view bytes, std::size_t from);

// Leading CRLFs before a request line (RFC 9112 2.2), as a count of bytes.
std::size_t leading_empty_lines(std::string_view bytes);

}  // namespace compaction::server
