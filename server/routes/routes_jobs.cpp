// /api/v1/jobs (the run table: filters, order, pages, CSV; show, artifacts), /api/v1/phase-map
// and the regions its labels predict. The table's pages, the map and the regions are the
// answers clients poll: served through the answer cache (ETag, If-None-Match).
#include "routes/app.hpp"
#include "routes/checkpoint_routes.hpp"

#include <map>
#include <memory>

#include <spdlog/spdlog.h>

#include "compaction/params.hpp"
#include "compaction/params_json.hpp"
#include "exchange/result_intake.hpp"
#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "input/safe_text.hpp"
#include "plan/counted_label.hpp"
#include "plan/phase_regions.hpp"
#include "routes/run_query.hpp"
#include "views/run_table_views.hpp"
#include "views/views.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// Rows of the CSV written at a time (about 100 kB).
constexpr int kCsvChunkRows = 500;

// The filters of /phase-map and /phase-map/regions: phi (required), one sweep, one grid, one
// geometry (the 2D pseudo-1D column unless named).
struct MapQuery {
  double phi = 0;
  std::optional<std::int64_t> sweep, cells_per_unit;
  std::string geometry = to_string(Geometry::pseudo1d);
};

MapQuery map_query(const httplib::Request& req) {
  MapQuery q;
  const auto phi = query_number(req, "phi");
  if (!phi) throw ApiError(422, "phi", "is required (e.g. ?phi=0.4)");
  q.phi = *phi;
  q.sweep = query_id(req, "sweep");
  if (req.has_param("cells_per_unit")) {
    q.cells_per_unit = query_int(req, "cells_per_unit", 0, static_cast<int>(limits::cells_per_unit.lo),
                                 static_cast<int>(limits::cells_per_unit.hi));
  }
  if (req.has_param("geometry")) {
    // Read as a scene's key, so the engine's one list of geometries decides.
    SceneParams scene;
    const std::string given = req.get_param_value("geometry");
    if (!read_json(json{{"geometry", given}}, scene).empty()) {
      throw ApiError(422, "geometry", "must be pseudo1d, full2d or pseudo1d_3d, got " +
                                          describe(json(valid_utf8(given))));
    }
    q.geometry = to_string(scene.geometry);
  }
  return q;
}

// The regions the map's labelled runs predict over the box of all its runs (none without runs),
// each point's replicates voting as one point.
std::optional<regions::Regions> predicted_regions(const std::vector<PhaseMapPoint>& points,
                                                  int grid) {
  std::vector<adaptive::Point> all;
  std::vector<std::pair<std::int64_t, adaptive::Labelled>> labelled;  // by point
  std::map<std::int64_t, int> runs_of;
  for (const PhaseMapPoint& p : points) {
    all.push_back({p.S, p.R});
    // The classifier's label counts from a stable run's result (an unstable run's label is not
    // the pattern's); a person's label on a finished run counts as the planner reads it.
    if (p.state != "succeeded") continue;
    const bool stable = p.status == std::optional<std::string>("ok");
    adaptive::Labelled l = counted_label({p.S, p.R}, p.human_label, stable ? p.cls : std::nullopt,
                                         p.confidence, p.runner_up);
    if (!l.label) continue;
    const std::int64_t point = p.point_id ? p.point_id : -p.job_id;
    ++runs_of[point];
    labelled.emplace_back(point, std::move(l));
  }
  const auto box = regions::box_of(all);
  if (!box) return std::nullopt;
  std::vector<adaptive::Labelled> votes;
  for (auto& [point, l] : labelled) {
    l.share = 1.0 / runs_of[point];
    votes.push_back(std::move(l));
  }
  return regions::predict(votes, *box, grid);
}

template <typename T>
views::PageInfo page_info(const RunQuery& q, const RunPage<T>& page) {
  return {page.total, q.limit, q.offset, sort_text(q.sort),
          page.next ? std::optional<std::string>(cursor_text(q.sort, *page.next)) : std::nullopt};
}

// The run table's rows as CSV, streamed: read in one read transaction that the answer holds
// until its last row is written; X-Total-Count is the filtered set's size, X-Row-Limit the most
// rows the answer holds.
void stream_csv(App& app, const RunQuery& q, std::vector<std::size_t> columns,
                httplib::Response& res) {
  std::shared_ptr<RunTable::Stream> rows = app.store.runs.stream(q);
  res.status = 200;
  res.set_header("X-Total-Count", std::to_string(rows->total()));
  res.set_header("X-Row-Limit", std::to_string(q.limit));
  res.set_header("Content-Disposition", "attachment; filename=\"jobs.csv\"");
  res.set_chunked_content_provider(
      "text/csv; charset=utf-8",
      [rows, columns = std::move(columns), header = true](std::size_t, httplib::DataSink& sink) mutable {
        // The provider runs after the handler, outside guarded(): a failure ends the answer
        // short (the chunked body never ends), and the client sees it cut.
        try {
          std::string chunk = header ? views::run_csv_header(columns) : "";
          header = false;
          RunRow row;
          int n = 0;
          while (n < kCsvChunkRows && rows->next(row)) {
            views::append_run_csv_line(chunk, row, columns);
            ++n;
          }
          if (!chunk.empty() && !sink.write(chunk.data(), chunk.size())) return false;
          if (n < kCsvChunkRows) sink.done();
          return true;
        } catch (const std::exception& e) {
          spdlog::error("GET /jobs?format=csv ended early: {}", e.what());
          return false;
        }
      });
}

}  // namespace

void register_job_routes(httplib::Server& server, App& app) {
  add_route(server, endpoints::list_jobs, [&app](const httplib::Request& req, httplib::Response& res) {
    const JobsRequest r = read_jobs_request(req);
    if (r.format == JobsFormat::csv) {
      stream_csv(app, r.query, views::answer_columns(r.columns), res);
      return;
    }
    app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
      if (r.format == JobsFormat::table) {
        const RunPage<RunRow> page = app.store.runs.page(r.query);
        return json_text(views::run_table(page.items, page_info(r.query, page), views::answer_columns(r.columns)));
      }
      const RunPage<JobRecord> page = app.store.reads.jobs(r.query);
      return json_text(views::jobs(page.items, page_info(r.query, page)));
    });
  });

  add_route(server, endpoints::show_job,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const auto j = app.store.reads.job(path_id(req, 1, "job"));
               if (!j) throw ApiError(404, "id", "no such job");
               json out = views::job_detail(*j);
               // Results of the same computation from other servers that differ from this one.
               out["conflicting_results"] = json::array();
               for (const std::string& c : app.store.imports.conflicts(j->job.id)) {
                 out["conflicting_results"].push_back(json::parse(c));
               }
               add_checkpoint_detail(app, j->job.id, out);
               send_json(res, 200, out);
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
               const MapQuery q = map_query(req);
               app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
                 return views::phase_map(
                     q.phi, app.store.reads.phase_map(q.phi, q.sweep, q.cells_per_unit, q.geometry));
               });
             });

  add_route(server, endpoints::phase_regions,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const MapQuery q = map_query(req);
               if (!limits::phi.contains(q.phi)) {
                 throw ApiError(422, "phi", "must be in " + to_string(limits::phi));
               }
               const int grid = query_int(req, "grid", regions::kDefaultGrid, regions::kMinGrid,
                                          regions::kMaxGrid);
               app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
                 return json_text(views::phase_regions(
                     q.phi, q.sweep, q.cells_per_unit,
                     predicted_regions(app.store.reads.phase_map(q.phi, q.sweep, q.cells_per_unit, q.geometry),
                                       grid)));
               });
             });
}

}  // namespace compaction::server
