// The tokens the server accepts, by role, and whose they are. A role without any token is open
// (a loopback server for one person); with tokens, a request to one of the role's endpoints
// carries "Authorization: Bearer TOKEN" with one of them. Tokens come from --submit-token and
// --worker-token (unnamed) and from --tokens FILE (named, one per line: ROLE NAME TOKEN), so
// that what a token did (a relabel, an import) is recorded with its name.
#pragma once

#include <string>
#include <vector>

#include <httplib.h>

namespace compaction::server {

// Who may call an endpoint: anyone, holders of a submit token, holders of a worker token.
enum class TokenKind { none, submit, worker };

struct Token {
  TokenKind role = TokenKind::submit;
  std::string name;    // empty for --submit-token / --worker-token
  std::string secret;
};

// Names: letters, digits, '.', '_', '-', 1 to 64; secrets: 8 to 256 printable characters
// without spaces (the command-line tokens: any non-empty text, as before).
inline constexpr std::size_t kTokenNameMaxBytes = 64;

class TokenTable {
 public:
  // Throws std::invalid_argument for a name or secret that breaks the rules above, or a secret
  // that another token already has.
  void add(Token token, bool from_file);

  bool open(TokenKind role) const;
  bool empty() const { return tokens_.empty(); }

  // The token of `role` that the request carries: nullptr when the role is open; throws
  // ApiError 401 (missing or malformed) or 403 (no such token) otherwise. The comparison takes
  // the same time wherever a wrong token differs.
  const Token* authenticate(const httplib::Request& req, TokenKind role) const;

  // Who made a request of `role`, for the records: "open" (the role needs no token), "submit"
  // or "worker" (the command-line token), "submit:alice" (a named token). The request passed
  // the guard, so its token is one of the table's.
  std::string identity(const httplib::Request& req, TokenKind role) const;

 private:
  std::vector<Token> tokens_;
};

// Adds the tokens of a --tokens file: one per line, "ROLE NAME TOKEN" (ROLE: submit or worker),
// blank lines and lines starting with '#' skipped. Throws std::invalid_argument naming the
// file and line.
void load_tokens_file(const std::string& path, TokenTable& table);

}  // namespace compaction::server
