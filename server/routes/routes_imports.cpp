// POST /api/v1/imports: merges another server's export (the body, an export file) into this
// database, as compaction-server --import does (import_store.hpp has the rule). The submit
// token is checked by the request guard before the body is read; the body is bounded by
// --max-upload-mb and goes to a spool file beside the database as it arrives, never into
// memory whole; the file is then read one run at a time. A file that fails a check is a 422
// naming its field, and nothing is stored.
#include <spdlog/spdlog.h>

#include "exchange/import_command.hpp"
#include "exchange/spool_file.hpp"
#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "routes/app.hpp"
#include "store/clock.hpp"

namespace compaction::server {

void register_import_routes(httplib::Server& server, App& app) {
  add_streaming_route(server, endpoints::import_sweep,
                      [&app](const httplib::Request& req, httplib::Response& res,
                             const httplib::ContentReader& read_body) {
    SpoolFile body(app.store.db.files.root());
    const bool complete = read_body([&body](const char* data, std::size_t size) {
      body.append(data, size);
      return true;
    });
    if (!complete) throw ApiError(400, "body", "the body ended before its Content-Length");
    const std::string importer = app.options.tokens.identity(req, endpoints::import_sweep.token);
    const ImportOutcome o = import_export(app.store, body.read(), importer, now_ms());
    spdlog::info("import by {}: sweep {} ({}), {} runs: {} new, {} filled, {} identical, {} "
                 "conflicting",
                 importer, o.sweep_id, o.sweep_created ? "created" : "existing", o.runs, o.added,
                 o.filled, o.identical, o.conflicts);
    // Local adaptive sweeps may hold jobs that just got their results.
    if (o.added + o.filled > 0) app.adaptive.advance_all(app.store, app.limits, now_ms());
    send_json(res, 200, import_outcome_json(o));
  });
}

}  // namespace compaction::server
