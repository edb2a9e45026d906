#include "store/label_store.hpp"

namespace compaction::server {

namespace {

// The job's current human label and classifier label; nullopt outcome when it can be labelled.
struct Current {
  std::optional<std::string> human, classifier;
};

std::optional<LabelOutcome> current_labels(sqlite::Database& db, std::int64_t job_id, Current& c) {
  if (!db.has_row("SELECT 1 FROM jobs WHERE id = ?", job_id)) return LabelOutcome::unknown_job;
  auto r = db.prepare(
      "SELECT r.class, h.label FROM results r LEFT JOIN human_labels h ON h.job_id = r.job_id"
      " WHERE r.job_id = ?");
  r.bind(1, job_id);
  if (!r.step()) return LabelOutcome::no_result;
  c.classifier = r.opt_text(0);
  c.human = r.opt_text(1);
  return std::nullopt;
}

// A row of the audit: the change, who made it and when; an imported change also what its source
// claims.
struct Change {
  const char* action;
  std::optional<std::string> label;
  std::string reason, by;
  Millis at;
  std::string token;
  std::optional<std::string> claimed_by;
  std::optional<Millis> claimed_at;
};

void log_change(sqlite::Database& db, std::int64_t job_id, const Current& c, const Change& x) {
  db.prepare(
        "INSERT INTO label_audit (job_id, action, label, previous_label, classifier_label, reason,"
        " set_by, at, token, claimed_by, claimed_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)")
      .bind(1, job_id)
      .bind(2, x.action)
      .bind(3, x.label)
      .bind(4, c.human)
      .bind(5, c.classifier)
      .bind(6, x.reason)
      .bind(7, x.by)
      .bind(8, x.at)
      .bind(9, x.token)
      .bind(10, x.claimed_by)
      .bind(11, x.claimed_at)
      .run();
}

void upsert(sqlite::Database& db, std::int64_t job_id, const HumanLabel& l) {
  db.prepare(
        "INSERT INTO human_labels (job_id, label, reason, set_by, set_at, token, imported_at)"
        " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7) ON CONFLICT (job_id) DO UPDATE SET label = ?2,"
        " reason = ?3, set_by = ?4, set_at = ?5, token = ?6, imported_at = ?7")
      .bind(1, job_id)
      .bind(2, l.label)
      .bind(3, l.reason)
      .bind(4, l.by)
      .bind(5, l.at)
      .bind(6, l.token)
      .bind(7, l.imported_at)
      .run();
}

}  // namespace

LabelOutcome LabelStore::set(std::int64_t job_id, const HumanLabel& l) {
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  Current c;
  if (const auto refused = current_labels(db_.writer, job_id, c)) return *refused;
  upsert(db_.writer, job_id, l);
  log_change(db_.writer, job_id, c, {"set", l.label, l.reason, l.by, l.at, l.token, {}, {}});
  tx.commit();
  db_.wait_durable(lock);
  return LabelOutcome::ok;
}

LabelOutcome LabelStore::clear(std::int64_t job_id, const std::string& reason,
                               const std::string& by, const std::string& token, Millis now) {
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  Current c;
  if (const auto refused = current_labels(db_.writer, job_id, c)) return *refused;
  if (!c.human) return LabelOutcome::not_labelled;
  db_.writer.prepare("DELETE FROM human_labels WHERE job_id = ?").bind(1, job_id).run();
  log_change(db_.writer, job_id, c, {"cleared", std::nullopt, reason, by, now, token, {}, {}});
  tx.commit();
  db_.wait_durable(lock);
  return LabelOutcome::ok;
}

bool LabelStore::import_label(sqlite::Database& writer, std::int64_t job_id,
                              const HumanLabel& l, const std::string& note,
                              const std::string& importer, Millis now) {
  Current c;
  if (current_labels(writer, job_id, c) || c.human) return false;
  HumanLabel here = l;
  here.token = importer;
  here.imported_at = now;
  upsert(writer, job_id, here);
  log_change(writer, job_id, c,
             {"imported", l.label, l.reason + " (" + note + ")", importer, now, importer, l.by, l.at});
  return true;
}

std::vector<LabelChange> LabelStore::audit(std::optional<std::int64_t> job_id, int limit,
                                           int offset, std::int64_t& total) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT id, job_id, action, label, previous_label, classifier_label, reason, set_by, at,"
      " token, claimed_by, claimed_at"
      " FROM label_audit WHERE (?1 IS NULL OR job_id = ?1) ORDER BY id DESC LIMIT ?2 OFFSET ?3");
  s.bind(1, job_id).bind(2, limit).bind(3, offset);
  std::vector<LabelChange> out;
  while (s.step()) {
    out.push_back({s.int64(0), s.int64(1), s.text(2), s.opt_text(3), s.opt_text(4), s.opt_text(5),
                   s.text(6), s.text(7), s.int64(8), s.opt_text(9), s.opt_text(10),
                   s.opt_int64(11)});
  }
  auto n = db->prepare("SELECT count(*) FROM label_audit WHERE (?1 IS NULL OR job_id = ?1)");
  n.bind(1, job_id);
  n.step();
  total = n.int64(0);
  return out;
}

}  // namespace compaction::server
