// Helpers shared by the route files: JSON answers, the error body, body parsing and query
// parameters. Every handler runs inside guarded(), which turns ApiError into its status
// and JSON body and anything else into a 500 saying "internal error" and an id; the reason is
// logged under that id and never sent.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "input/api_error.hpp"

namespace compaction::server {

// A JSON document as the API sends it: strings from clients may hold invalid UTF-8, replaced
// (U+FFFD), never a throw.
std::string json_text(const nlohmann::json& body);
void send_json(httplib::Response& res, int status, const nlohmann::json& body);
void send_error(httplib::Response& res, const ApiError& e);
// A 500 with a new error id; the reason goes to the log under the id.
void send_internal_error(const httplib::Request& req, httplib::Response& res,
                         const std::string& what);

using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
Handler guarded(Handler h);

// The request body as a JSON value; malformed or too deeply nested JSON is a 400 naming
// the field "body".
nlohmann::json parse_json_body(const httplib::Request& req);

// Path ids: positive integers (the route's regex guarantees digits; too large -> 404).
std::int64_t path_id(const httplib::Request& req, int match_index, const char* what);

// A number given as text (a query parameter, a form field): the whole text in decimal (no
// spaces, no hex, no "nan" or "inf"), finite and not beyond double's range either way (1e-400
// is refused, not read as 0).
std::optional<double> decimal_number(const std::string& text);

// Query parameters: absent -> fallback/nullopt; malformed or out of range -> 422 naming it.
int query_int(const httplib::Request& req, const char* name, int fallback, int lo, int hi);
std::optional<std::int64_t> query_id(const httplib::Request& req, const char* name);
std::optional<double> query_number(const httplib::Request& req, const char* name);

// Required string fields of a JSON object body (422 naming the field): 1 to max_len bytes;
// a name holds no control characters; prose (a person's reason for a label) is valid UTF-8 and
// may hold newlines and tabs but no other control character (no NUL: SQLite's length() stops
// at one); free text (a runner's failure reason) is kept as it came (the log escapes it, JSON
// answers escape it).
enum class TextKind { name, prose, free_text };
std::string body_string(const nlohmann::json& body, const char* key, std::size_t max_len,
                        TextKind text = TextKind::name);

}  // namespace compaction::server
