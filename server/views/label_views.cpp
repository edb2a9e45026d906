#include "views/label_views.hpp"

#include "views/json_opt.hpp"

namespace compaction::server::views {

using nlohmann::json;

json human_label(const std::optional<HumanLabel>& l) {
  if (!l) return nullptr;
  return {{"label", l->label},
          {"reason", l->reason},
          {"by", l->by},
          {"at", l->at},
          {"token", l->token.empty() ? json(nullptr) : json(l->token)},
          {"imported_at", opt(l->imported_at)}};
}

json label_change(const LabelChange& c) {
  return {{"id", c.id},
          {"job_id", c.job_id},
          {"action", c.action},
          {"label", opt(c.label)},
          {"previous_label", opt(c.previous_label)},
          {"classifier_label", opt(c.classifier_label)},
          {"reason", c.reason},
          {"by", c.by},
          {"at", c.at},
          {"token", opt(c.token)},
          {"claimed_by", opt(c.claimed_by)},
          {"claimed_at", opt(c.claimed_at)}};
}

json label_audit(const std::vector<LabelChange>& changes, std::int64_t total, int limit,
                 int offset) {
  json out = json::array();
  for (const LabelChange& c : changes) out.push_back(label_change(c));
  return {{"changes", out}, {"total", total}, {"limit", limit}, {"offset", offset}};
}

json result_origin(const StoredResult& r) {
  if (!r.origin_database) return nullptr;
  return {{"database", *r.origin_database},
          {"job", opt(r.origin_job)},
          {"imported_at", opt(r.imported_at)}};
}

json sweep_origin(const SweepRecord& s) {
  if (!s.origin_database) return nullptr;
  json out = s.origin ? json::parse(*s.origin) : json::object();
  out["database"] = *s.origin_database;
  out["sweep"] = opt(s.origin_sweep);
  return out;
}

}  // namespace compaction::server::views
