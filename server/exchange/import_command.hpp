// Imports of another server's export (export_format.hpp): compaction-server --import FILE merges
// a file into the database of --db and exits without serving (the database's server stopped: it
// holds the database's lock), and POST /api/v1/imports does the same on a running server.
#pragma once

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "config/options.hpp"
#include "store/clock.hpp"
#include "store/import_store.hpp"

namespace compaction::server {

struct Store;

// The outcome as the CLI prints it and POST /api/v1/imports answers it.
nlohmann::json import_outcome_json(const ImportOutcome& o);

// Reads, checks and merges the file `in` (ImportStore::import_file), then removes the
// checkpoints of the jobs it filled, as a worker's completion does. Throws ApiError (the file)
// or std::runtime_error (the database, the disk); nothing is stored then.
ImportOutcome import_export(Store& store, std::FILE* in, const std::string& importer, Millis now);

// Reads, checks and merges the file; prints the outcome as JSON on stdout. Returns the exit
// code: 0 merged (or nothing to merge), 1 the file is unreadable or invalid (the message names
// the field; nothing is stored), the database is held by a running server, or it failed.
int run_import(const ServerOptions& options, const std::string& file);

}  // namespace compaction::server
