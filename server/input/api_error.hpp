// An error answered to an HTTP client: a status code and the field it is about.
// Body: {"error": {"field": "S.min", "message": "...", "details": [{"field", "message"}...]}}.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction::server {

struct ApiError : std::runtime_error {
  ApiError(int status, std::string field, const std::string& message)
      : std::runtime_error(message), status(status), field(std::move(field)) {}
  // Several problems at once: the first names the error, all are listed in "details".
  ApiError(int status, std::vector<FieldError> all)
      : std::runtime_error(all.empty() ? "invalid input" : all.front().message),
        status(status),
        field(all.empty() ? "" : all.front().field),
        details(std::move(all)) {}

  nlohmann::json body() const {
    nlohmann::json e = {{"field", field}, {"message", what()}};
    if (details.size() > 1) {
      e["details"] = nlohmann::json::array();
      for (const auto& d : details) e["details"].push_back({{"field", d.field}, {"message", d.message}});
    }
    return {{"error", e}};
  }

  int status;
  std::string field;
  std::vector<FieldError> details;
};

}  // namespace compaction::server
