// An optional value as JSON: the value, or null. The REST views and the export file write every
// optional field of a record this way.
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

namespace compaction::server {

template <typename T>
nlohmann::json opt(const std::optional<T>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

}  // namespace compaction::server
