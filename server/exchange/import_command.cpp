#include "exchange/import_command.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include <spdlog/spdlog.h>

#include "compaction/result.hpp"
#include "exchange/export_format.hpp"
#include "http/http_util.hpp"
#include "input/api_error.hpp"
#include "store/clock.hpp"
#include "store/store.hpp"

namespace compaction::server {

using nlohmann::json;

json import_outcome_json(const ImportOutcome& o) {
  return {{"sweep_id", o.sweep_id}, {"sweep_created", o.sweep_created},
          {"runs", o.runs},         {"added", o.added},
          {"filled", o.filled},     {"identical", o.identical},
          {"conflicts", o.conflicts}, {"conflicts_known", o.conflicts_known},
          {"linked", o.linked},     {"labels", o.labels},
          {"changed", o.changed()}};
}

ImportOutcome import_export(Store& store, std::FILE* in, const std::string& importer, Millis now) {
  const ImportOutcome o = store.imports.import_file(
      [in](const RunSink& on_run) { return read_export(in, on_run); }, importer, now);
  for (const std::int64_t job : o.filled_jobs) store.checkpoints.remove_if_done(job);
  return o;
}

int run_import(const ServerOptions& options, const std::string& file) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(file.c_str(), "rb"), &std::fclose);
  if (!in) {
    spdlog::error("--import {}: cannot read the file: {}", file, std::strerror(errno));
    return 1;
  }
  try {
    StoreConfig config;
    config.engine_version = compaction::engine_version();
    const std::filesystem::path db_path(options.db);
    if (db_path.has_parent_path()) std::filesystem::create_directories(db_path.parent_path());
    Store store(options.db, config);
    const ImportOutcome o = import_export(store, in.get(), "command line", now_ms());
    spdlog::info("imported {} into {}: sweep {} ({}), {} runs: {} new, {} filled, {} identical, "
                 "{} conflicting ({} known), {} labels",
                 file, options.db, o.sweep_id, o.sweep_created ? "created" : "existing", o.runs,
                 o.added, o.filled, o.identical, o.conflicts, o.conflicts_known, o.labels);
    std::cout << json_text(import_outcome_json(o)) << "\n";
    return 0;
  } catch (const ApiError& e) {
    spdlog::error("--import {}: {}: {} (nothing imported)", file, e.field, e.what());
  } catch (const std::exception& e) {
    spdlog::error("--import {}: {} (nothing imported)", file, e.what());
  }
  return 1;
}

}  // namespace compaction::server
