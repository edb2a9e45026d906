// compaction-server --import FILE: merges an export file (export_format.hpp) into the database
// of --db and exits, without serving. Run it with that database's server stopped, or post the
// file to a running server instead (POST /api/v1/imports).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "import_store.hpp"
#include "options.hpp"

namespace compaction::server {

// The outcome as the CLI prints it and POST /api/v1/imports answers it.
nlohmann::json import_outcome_json(const ImportOutcome& o);

// Reads, checks and merges the file; prints the outcome as JSON on stdout. Returns the exit
// code: 0 merged (or nothing to merge), 1 the file is unreadable or invalid (the message names
// the field; nothing is stored) or the database failed.
int run_import(const ServerOptions& options, const std::string& file);

}  // namespace compaction::server
