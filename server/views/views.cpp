#include "views/views.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "compaction/params.hpp"
#include "plan/cost_model.hpp"
#include "plan/map_points.hpp"
#include "plan/planner.hpp"
#include "store/run_table.hpp"
#include "views/json_opt.hpp"
#include "views/label_views.hpp"

namespace compaction::server::views {

using nlohmann::json;

namespace {

// Appends JSON values to a text: a double as the shortest text that reads back as the same
// double (std::to_chars; integral ones with ".0", as nlohmann writes them), strings through
// nlohmann (escapes, invalid UTF-8 replaced).
struct JsonText {
  std::string out;

  JsonText& key(const char* k) {
    if (out.back() != '{') out += ',';
    out += '"';
    out += k;
    out += "\":";
    return *this;
  }
  void value(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    const std::string_view s(buf, static_cast<std::size_t>(r.ptr - buf));
    out += s;
    if (s.find_first_of(".e") == std::string_view::npos) out += ".0";
  }
  void value(std::int64_t v) { out += std::to_string(v); }
  void value(bool v) { out += v ? "true" : "false"; }
  void value(const std::string& v) {
    // Printable ASCII without a quote or a backslash is its own JSON text; anything else (an
    // escape, or UTF-8 that may be invalid) goes through the library's writer.
    const bool plain = std::all_of(v.begin(), v.end(), [](char c) {
      return c >= 0x20 && c < 0x7f && c != '"' && c != '\\';
    });
    if (plain) {
      out += '"';
      out += v;
      out += '"';
    } else {
      out += json(v).dump(-1, ' ', false, json::error_handler_t::replace);
    }
  }
  template <typename T>
  void value(const std::optional<T>& v) {
    if (v) {
      value(*v);
    } else {
      out += "null";
    }
  }
};

json counts(const StateCounts& c) {
  return {{"queued", c.queued},       {"running", c.running},     {"succeeded", c.succeeded},
          {"failed", c.failed},       {"cancelled", c.cancelled}, {"total", c.total()}};
}

}  // namespace

json sweep(const SweepRecord& s) {
  const char* state = s.cancelled_at ? "cancelled" : s.counts.open() > 0 ? "active" : "done";
  const std::int64_t total = s.counts.total();
  const std::int64_t finished = total - s.counts.open();
  return {{"id", s.id},
          {"name", s.name},
          {"request", json::parse(s.request)},
          {"priority", s.priority},
          {"created_at", s.created_at},
          {"cancelled_at", opt(s.cancelled_at)},
          {"state", state},
          {"counts", counts(s.counts)},
          {"progress", total > 0 ? static_cast<double>(finished) / total : 1.0},
          {"phis", request_phis(json::parse(s.request))},
          {"imported", sweep_origin(s)}};
}

json sweeps(const Page<SweepRecord>& page, int limit, int offset) {
  json out = json::array();
  for (const SweepRecord& s : page.items) out.push_back(sweep(s));
  return {{"sweeps", out}, {"total", page.total}, {"limit", limit}, {"offset", offset}};
}

json created_sweep(const SweepRecord& s, const CreatedSweep& c, const std::string& preset) {
  json out = sweep(s);
  out["created"] = {{"jobs", c.n_jobs},     {"new", c.n_new},
                    {"reused", c.n_reused}, {"shared", c.n_shared},
                    {"requeued", c.n_requeued}, {"preset", preset}};
  return out;
}

json cancelled_sweep(std::int64_t id, std::int64_t cancelled_jobs) {
  return {{"id", id}, {"cancelled_jobs", cancelled_jobs}};
}

namespace {

// A number of CPU seconds as CPU-hours, null for an infinite budget.
json cpu_hours(double seconds) { return std::isfinite(seconds) ? json(seconds / 3600.0) : json(nullptr); }

}  // namespace

json sweep_plan(std::int64_t id, const PlanReport& r, std::size_t limit) {
  // Where the sweep stands. "planning": nothing pending, but runs worth queueing and budget
  // for them, which the planner is adding (a result has just been stored; the jobs follow in
  // the next transaction). Once neither is left, the runs decide.
  const std::size_t budget_left = r.spec.budget - std::min(r.spec.budget, r.done + r.pending);
  const double cpu_left = r.budget_cpu_seconds - r.cpu_seconds;
  const bool fits = std::any_of(r.candidates.begin(), r.candidates.end(), [&](const auto& a) {
    return a.cpu_seconds <= cpu_left;
  });
  const char* state = r.cancelled                                       ? "cancelled"
                      : r.pending > 0                                   ? "running"
                      : !r.candidates.empty() && budget_left > 0 && fits ? "planning"
                      : r.resolved                                      ? "resolved"
                      : budget_left == 0 || !r.candidates.empty()       ? "budget_spent"
                                                                        : "unresolved";
  const adaptive::Steps steps = adaptive::finest_steps(r.spec);
  // The lattice of the finest steps, both ends included: the full grid that resolves every
  // boundary as finely as the sweep does.
  const auto nodes = [](const adaptive::AxisRange& a, double step) {
    return static_cast<long long>(std::llround(std::log10(a.max / a.min) / step)) + 1;
  };
  const long long n_S = nodes(r.spec.S, steps.S), n_R = nodes(r.spec.R, steps.R);
  json candidates = json::array();
  for (std::size_t i = 0; i < r.candidates.size() && i < limit; ++i) {
    const adaptive::LevelAction& a = r.candidates[i];
    candidates.push_back({{"S", a.point.S}, {"R", a.point.R}, {"level", a.level},
                          {"replicate", a.replicate}, {"why", a.why}, {"value", a.value},
                          {"cpu_seconds", a.cpu_seconds}});
  }
  json levels = json::array();
  for (const LevelReport& l : r.levels) {
    levels.push_back({{"cells_per_unit", l.cells_per_unit},
                      {"points", l.points},
                      {"robust", l.robust},
                      {"runs", {{"done", l.runs_done}, {"pending", l.runs_pending}}},
                      {"cpu_hours", {{"done", l.cpu_seconds_done / 3600.0},
                                     {"pending", l.cpu_seconds_pending / 3600.0}}},
                      {"next", {{"runs", l.next_runs}, {"cpu_hours", l.next_cpu_seconds / 3600.0}}}});
  }
  json columns = json::array();
  for (const adaptive::ColumnResolution& c : r.columns) {
    columns.push_back({{"S", c.S},
                       {"points", c.points},
                       {"boundaries", c.boundaries},
                       {"bracket_decades", c.bracket_decades ? json(*c.bracket_decades) : json(nullptr)},
                       {"resolved", c.resolved},
                       {"finest_level", c.finest_level}});
  }
  return {{"id", id},
          {"state", state},
          {"resolved", r.resolved},
          {"replicates", r.replicates},
          {"runs", {{"done", r.done},
                    {"pending", r.pending},
                    {"budget", r.spec.budget},
                    {"budget_left", budget_left}}},
          {"cpu_hours", {{"spent", r.cpu_seconds / 3600.0},
                         {"budget", cpu_hours(r.budget_cpu_seconds)},
                         {"budget_left", cpu_hours(cpu_left)}}},
          {"levels", levels},
          {"lattice", {{"step_S_decades", steps.S},
                       {"step_R_decades", steps.R},
                       {"S", n_S},
                       {"R", n_R},
                       {"points", n_S * n_R},
                       {"runs", n_S * n_R * static_cast<long long>(r.replicates)}}},
          {"columns", columns},
          {"candidates_total", r.candidates.size()},
          {"candidates", candidates}};
}

json job(const JobRecord& j) {
  json scene = json::parse(j.scene);
  const double strut = cells_per_strut(j.cells_per_unit, j.phi, scene.value("geometry", "pseudo1d"));
  json out = {{"id", j.id},
              {"state", j.state},
              {"S", j.S},
              {"R", j.R},
              {"phi", j.phi},
              {"cells_per_unit", j.cells_per_unit},
              {"cells_per_strut", strut},
              {"eps_end", j.eps_end},
              {"point_id", j.point_id},
              {"engine_version", j.engine_version},
              {"scene", std::move(scene)},
              {"priority", j.priority},
              {"attempts", j.attempts},
              {"max_attempts", j.max_attempts},
              {"worker", opt(j.worker)},
              {"progress_eps", opt(j.progress_eps)},
              {"created_at", j.created_at},
              {"started_at", opt(j.started_at)},
              {"heartbeat_at", opt(j.heartbeat_at)},
              {"finished_at", opt(j.finished_at)},
              {"run_after", j.run_after},
              {"lease_deadline", opt(j.lease_deadline)},
              {"last_error", opt(j.last_error)},
              {"result", nullptr}};
  if (j.result) {
    const StoredResult& r = *j.result;
    out["result"] = {{"status", r.status},
                     {"reason", r.reason},
                     {"class", opt(r.cls)},
                     {"confidence", opt(r.confidence)},
                     {"runner_up", opt(r.runner_up)},
                     {"n_reflections", opt(r.n_reflections)},
                     {"band_speed_ratio", opt(r.band_speed_ratio)},
                     {"features", r.features ? json::parse(*r.features) : json(nullptr)},
                     {"engine_version", r.engine_version},
                     {"source_revision", r.source_revision},
                     {"eps_reached", opt(r.eps_reached)},
                     {"wall_seconds", opt(r.wall_seconds)},
                     {"worker", r.worker},
                     {"created_at", r.created_at},
                     {"origin", result_origin(r)}};
  }
  out["human_label"] = human_label(j.human_label);
  return out;
}

json job_detail(const JobDetail& d) {
  json j = job(d.job);
  j["sweeps"] = d.sweeps;
  j["replicates"] = d.replicates;
  j["events"] = json::array();
  for (const EventRecord& e : d.events) {
    j["events"].push_back({{"at", e.at},
                           {"kind", e.kind},
                           {"attempt", e.attempt},
                           {"worker", opt(e.worker)},
                           {"message", e.message}});
  }
  j["events_dropped"] = d.events_dropped;
  if (!j["result"].is_null() && d.summary) j["result"]["summary"] = json::parse(*d.summary);
  return j;
}

json sweep_jobs(const std::vector<JobRecord>& rows) {
  json out = json::array();
  for (const JobRecord& j : rows) out.push_back(job(j));
  return out;
}

json model(double phi) {
  if (!(phi > 0.0 && phi < 1.0)) return nullptr;
  return {{"strut_fraction", strut_fraction(phi)},
          {"strut_aspect_ratio", strut_aspect_ratio(phi)},
          {"buckling_R", buckling_onset_R(phi)},
          {"nonreflecting_band_speed", nonreflecting_band_speed(phi)}};
}

namespace {

// A reading's spread over a point's replicates: {mean, n, sd}, or null when no run has it.
void spread_value(JsonText& t, const std::optional<Spread>& s) {
  if (!s) {
    t.out += "null";
    return;
  }
  t.out += '{';
  t.key("mean").value(s->mean);
  t.key("n").value(static_cast<std::int64_t>(s->n));
  t.key("sd").value(s->sd);
  t.out += '}';
}

// One point of the map (map_points.hpp), keys sorted as a json object writes them.
void point_summary(JsonText& t, const MapPoint& p) {
  const Tally& k = p.tally;
  t.out += '{';
  t.key("R").value(p.R);
  t.key("S").value(p.S);
  t.key("band_speed_early");
  spread_value(t, p.band_speed_early);
  t.key("band_speed_lead");
  spread_value(t, p.band_speed_lead);
  t.key("band_speed_ratio");
  spread_value(t, p.band_speed_ratio);
  t.key("band_speed_transit");
  spread_value(t, p.band_speed_transit);
  t.key("cells_per_strut").value(cells_per_strut(p.cells_per_unit, p.phi, p.geometry));
  t.key("cells_per_unit").value(p.cells_per_unit);
  t.key("eps_end").value(p.eps_end);
  t.key("finished").value(static_cast<std::int64_t>(k.finished));
  t.key("jobs");
  t.out += '[';
  for (std::size_t i = 0; i < p.jobs.size(); ++i) {
    if (i) t.out += ',';
    t.value(p.jobs[i]);
  }
  t.out += ']';
  t.key("label").value(k.label);
  t.key("labelled").value(static_cast<std::int64_t>(k.labelled));
  t.key("n_reflections");
  spread_value(t, p.n_reflections);
  t.key("phi").value(p.phi);
  t.key("point_id").value(p.point_id);
  t.key("probabilities");
  t.out += '{';
  for (const auto& [label, share] : k.probabilities) t.key(label.c_str()).value(share);
  t.out += '}';
  t.key("robust").value(k.robust);
  t.key("runs").value(static_cast<std::int64_t>(k.runs));
  t.key("share");
  if (k.label) {
    t.value(k.share);
  } else {
    t.out += "null";
  }
  t.key("structure").value(p.structure);
  t.out += '}';
}

}  // namespace

std::string phase_map(double phi, const std::vector<PhaseMapPoint>& points) {
  // Keys in the order a json object writes them (sorted).
  JsonText t;
  t.out.reserve(64 + points.size() * 500);
  t.out += "{";
  t.key("model");
  t.out += model(phi).dump();
  t.key("phi").value(phi);
  t.key("points");
  t.out += '[';
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PhaseMapPoint& p = points[i];
    t.out += i == 0 ? "{" : ",{";
    t.key("R").value(p.R);
    t.key("S").value(p.S);
    t.key("band_speed_early").value(p.band_speed_early);
    t.key("band_speed_early_error").value(p.band_speed_early_error);
    t.key("band_speed_error").value(p.band_speed_error);
    t.key("band_speed_lead").value(p.band_speed_lead);
    t.key("band_speed_lead_error").value(p.band_speed_lead_error);
    t.key("band_speed_ratio").value(p.band_speed_ratio);
    t.key("band_speed_transit").value(p.band_speed_transit);
    t.key("band_speed_transit_error").value(p.band_speed_transit_error);
    t.key("cells_per_strut").value(cells_per_strut(p.cells_per_unit, p.phi, p.geometry));
    t.key("cells_per_unit").value(p.cells_per_unit);
    t.key("class").value(p.cls);
    t.key("confidence").value(p.confidence);
    t.key("eps_end").value(p.eps_end);
    t.key("human_label").value(p.human_label);
    t.key("job_id").value(p.job_id);
    t.key("n_reflections").value(p.n_reflections);
    t.key("phi").value(p.phi);
    t.key("point_id").value(p.point_id);
    t.key("progress_eps").value(p.progress_eps);
    t.key("runner_up").value(p.runner_up);
    t.key("state").value(p.state);
    t.key("status").value(p.status);
    t.key("structure").value(p.structure);
    t.out += '}';
  }
  t.out += ']';
  t.key("summaries");
  t.out += point_summaries(points);
  t.out += '}';
  return t.out;
}

std::string point_summaries(const std::vector<PhaseMapPoint>& runs) {
  JsonText t;
  t.out += '[';
  const std::vector<MapPoint> points = map_points(runs);
  for (std::size_t i = 0; i < points.size(); ++i) {
    t.out += i == 0 ? "" : ",";
    point_summary(t, points[i]);
  }
  t.out += ']';
  return t.out;
}

json artifacts(std::int64_t job_id, const std::vector<ArtifactInfo>& list) {
  json out = json::array();
  for (const ArtifactInfo& a : list) {
    out.push_back({{"name", a.name},
                   {"content_type", a.content_type},
                   {"size", a.size},
                   {"url", "/api/v1/jobs/" + std::to_string(job_id) + "/artifacts/" + a.name}});
  }
  return {{"job_id", job_id}, {"artifacts", out}};
}

json phase_regions(double phi, std::optional<std::int64_t> sweep,
                   std::optional<std::int64_t> cells_per_unit,
                   const std::optional<regions::Regions>& r) {
  json out = {{"phi", phi},
              {"sweep", opt(sweep)},
              {"cells_per_unit", opt(cells_per_unit)},
              {"rule",
               {{"bandwidth_decades", regions::kBandwidthDecades},
                {"cutoff_decades", regions::kCutoffSigmas * regions::kBandwidthDecades},
                {"evidence_scale", regions::kEvidenceScale}}}};
  if (!r) {  // no run at phi: nothing to draw
    out.update({{"grid", 0}, {"runs", 0}, {"S", nullptr}, {"R", nullptr},
                {"classes", json::array()}, {"uncertainty", json::array()}});
    return out;
  }
  json classes = json::array(), uncertainty = json::array();
  for (int j = 0; j < r->grid; ++j) {
    std::string row(static_cast<std::size_t>(r->grid), '.');
    json u = json::array();
    for (int i = 0; i < r->grid; ++i) {
      const regions::Cell& c = r->at(i, j);
      if (c.cls && c.cls->size() == 1) row[static_cast<std::size_t>(i)] = (*c.cls)[0];
      u.push_back(std::round(c.uncertainty * 1000) / 1000);
    }
    classes.push_back(std::move(row));
    uncertainty.push_back(std::move(u));
  }
  out.update({{"grid", r->grid},
              {"runs", r->runs},
              {"S", {{"log_min", r->box.log_S_min}, {"log_max", r->box.log_S_max}}},
              {"R", {{"log_min", r->box.log_R_min}, {"log_max", r->box.log_R_max}}},
              {"classes", std::move(classes)},
              {"uncertainty", std::move(uncertainty)}});
  return out;
}

json sweep_estimate(const SweepEstimate& e) {
  const auto finish = [&](double cpu) {
    return e.workers > 0 ? json(cpu / static_cast<double>(e.workers)) : json(nullptr);
  };
  return {{"jobs", e.jobs},
          {"max_jobs", e.max_jobs},
          {"cpu_seconds", e.cpu_seconds},
          {"cpu_hours", e.cpu_seconds / 3600},
          {"max_cpu_seconds", e.max_cpu_seconds},
          {"max_cpu_hours", e.max_cpu_seconds / 3600},
          {"ns_per_particle_step", cost::kNsPerParticleStep},
          {"workers", e.workers},
          {"workers_seen_within_seconds", e.lease_seconds},
          {"finish_seconds", finish(e.cpu_seconds)},
          {"max_finish_seconds", finish(e.max_cpu_seconds)}};
}

}  // namespace compaction::server::views
