#include "config/tokens.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "input/api_error.hpp"

namespace compaction::server {

namespace {

const char* role_name(TokenKind role) {
  return role == TokenKind::worker ? "worker" : role == TokenKind::submit ? "submit" : "none";
}

bool name_ok(const std::string& s) {
  return !s.empty() && s.size() <= kTokenNameMaxBytes &&
         std::all_of(s.begin(), s.end(), [](char c) {
           return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  c == '.' || c == '_' || c == '-';
         });
}

bool secret_ok(const std::string& s) {
  return s.size() >= 8 && s.size() <= 256 &&
         std::all_of(s.begin(), s.end(), [](char c) { return c > 0x20 && c < 0x7f; });
}

// Whether a equals b, in time that depends on the lengths only.
bool same(const std::string& a, const std::string& b) {
  if (b.empty()) return false;
  unsigned diff = a.size() != b.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    diff |= static_cast<unsigned char>(a[i]) ^ static_cast<unsigned char>(b[i % b.size()]);
  }
  return diff == 0;
}

}  // namespace

void TokenTable::add(Token token, bool from_file) {
  if (from_file && !name_ok(token.name)) {
    throw std::invalid_argument("a token's name is 1 to 64 letters, digits, '.', '_' or '-'");
  }
  if (from_file && !secret_ok(token.secret)) {
    throw std::invalid_argument("a token is 8 to 256 printable characters without spaces");
  }
  if (token.secret.empty()) throw std::invalid_argument("a token must not be empty");
  for (const Token& t : tokens_) {
    if (t.secret == token.secret) throw std::invalid_argument("two tokens are the same");
    if (!token.name.empty() && t.name == token.name && t.role == token.role) {
      throw std::invalid_argument("two " + std::string(role_name(token.role)) + " tokens are named " +
                                  token.name);
    }
  }
  tokens_.push_back(std::move(token));
}

bool TokenTable::open(TokenKind role) const {
  return role == TokenKind::none ||
         std::none_of(tokens_.begin(), tokens_.end(), [&](const Token& t) { return t.role == role; });
}

const Token* TokenTable::authenticate(const httplib::Request& req, TokenKind role) const {
  if (open(role)) return nullptr;
  const std::string auth = req.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (auth.empty()) throw ApiError(401, "Authorization", "a Bearer token is required");
  if (auth.rfind(prefix, 0) != 0) {
    throw ApiError(401, "Authorization", "expected \"Authorization: Bearer <token>\"");
  }
  const std::string given = auth.substr(prefix.size());
  const Token* found = nullptr;
  // Every token of the role is compared, so the time says nothing of which one is close.
  for (const Token& t : tokens_) {
    if (t.role == role && same(given, t.secret) && !found) found = &t;
  }
  if (!found) throw ApiError(403, "Authorization", "wrong token");
  return found;
}

std::string TokenTable::identity(const httplib::Request& req, TokenKind role) const {
  if (open(role)) return "open";
  try {
    const Token* t = authenticate(req, role);
    return t->name.empty() ? role_name(role) : std::string(role_name(role)) + ":" + t->name;
  } catch (const ApiError&) {
    return "unknown";  // the guard refuses such a request before its handler runs
  }
}

void load_tokens_file(const std::string& path, TokenTable& table) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(path + ": cannot read the file");
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + " line " + std::to_string(number) + ": ";
    std::istringstream words(line);
    std::string role, name, secret, extra;
    if (!(words >> role) || role[0] == '#') continue;
    if (!(words >> name >> secret) || (words >> extra)) {
      throw std::invalid_argument(where + "expected ROLE NAME TOKEN");
    }
    Token t;
    if (role == "submit") {
      t.role = TokenKind::submit;
    } else if (role == "worker") {
      t.role = TokenKind::worker;
    } else {
      throw std::invalid_argument(where + "the role is submit or worker, got \"" + role + "\"");
    }
    t.name = name;
    t.secret = secret;
    try {
      table.add(std::move(t), true);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(where + e.what());
    }
  }
}

}  // namespace compaction::server
