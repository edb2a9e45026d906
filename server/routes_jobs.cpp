// /api/v1/jobs (list with filters, show, artifacts) and /api/v1/phase-map. The list and the
// map are the answers clients poll: served through the answer cache (ETag, If-None-Match).
#include "app.hpp"
#include "endpoints.hpp"
#include "http_util.hpp"
#include "result_intake.hpp"
#include "views.hpp"

namespace compaction::server {

using nlohmann::json;

void register_job_routes(httplib::Server& server, App& app) {
  add_route(server, endpoints::list_jobs, [&app](const httplib::Request& req, httplib::Response& res) {
    JobFilter f;
    f.sweep_id = query_id(req, "sweep");
    if (req.has_param("state")) {
      f.state = parse_job_state(req.get_param_value("state"));
      if (!f.state) {
        throw ApiError(422, "state", "must be queued, running, succeeded, failed or cancelled");
      }
    }
    f.phi = query_number(req, "phi");
    f.limit = query_int(req, "limit", 100, 1, 1000);
    f.offset = query_int(req, "offset", 0, 0, 1000000000);
    app.answers.serve(req, res, app.store.db.writer.commits(),
                      [&] { return json_text(views::jobs(app.store.reads.jobs(f), f.limit, f.offset)); });
  });

  add_route(server, endpoints::show_job,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const auto j = app.store.reads.job(path_id(req, 1, "job"));
               if (!j) throw ApiError(404, "id", "no such job");
               send_json(res, 200, views::job_detail(*j));
             });

  add_route(server, endpoints::list_artifacts,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const std::int64_t id = path_id(req, 1, "job");
               const auto list = app.store.reads.artifacts(id);
               if (!list) throw ApiError(404, "id", "no such job");
               send_json(res, 200, views::artifacts(id, *list));
             });

  add_route(server, endpoints::artifact,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const std::int64_t id = path_id(req, 1, "job");
               const std::string name = req.matches[2];
               if (!valid_artifact_name(name)) throw ApiError(404, "name", "no such artifact");
               const auto a = app.store.reads.artifact(id, name);
               if (!a) throw ApiError(404, "name", "no such artifact for job " + std::to_string(id));
               res.status = 200;
               res.set_content(a->data, a->content_type.c_str());
             });

  add_route(server, endpoints::phase_map,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const auto phi = query_number(req, "phi");
               if (!phi) throw ApiError(422, "phi", "is required (e.g. ?phi=0.4)");
               const auto sweep = query_id(req, "sweep");
               app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
                 return views::phase_map(*phi, app.store.reads.phase_map(*phi, sweep));
               });
             });
}

}  // namespace compaction::server
