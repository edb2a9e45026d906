#include "store/import_store.hpp"

#include <malloc.h>

#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "input/api_error.hpp"
#include "store/label_store.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// The parts of a result that say what the run found; equal parts: the same result.
struct Verdict {
  std::string status, reason;
  std::optional<std::string> cls, runner_up, features;
  std::optional<double> confidence, band_speed_ratio, eps_reached;
  std::optional<std::int64_t> n_reflections;
  bool operator==(const Verdict&) const = default;
};

Verdict verdict_of(const ResultRecord& r) {
  return {r.status, r.reason, r.cls, r.runner_up, r.features, r.confidence, r.band_speed_ratio,
          r.eps_reached, r.n_reflections};
}

std::string random_hex(int bytes) {
  static thread_local std::random_device rd;
  static const char* hex = "0123456789abcdef";
  std::string s;
  for (int i = 0; i < bytes; ++i) {
    const unsigned v = rd() & 255u;
    s += hex[v >> 4];
    s += hex[v & 15u];
  }
  return s;
}

// The imported result with its files, its computing server's worker and time, and its origin.
void insert_imported(sqlite::Database& w, std::int64_t job_id, const ImportedRun& run,
                     const std::vector<std::string>& paths, Millis now) {
  insert_result(w, job_id, run.result, run.worker, run.result_created_at, paths,
                ResultOrigin{run.origin_database, run.origin_job, now});
}

std::string provenance_note(const ImportedRun& run) {
  return "imported: computed by database " + run.origin_database + " as job " +
         std::to_string(run.origin_job);
}

}  // namespace

std::string ImportStore::database_id() {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare("SELECT id FROM database_identity");
  if (!s.step()) throw sqlite::Error("database_identity is empty");
  return s.text(0);
}

// The artifact folders an import writes: removed when the import ends, but those its commit
// names.
struct ImportStore::Staging {
  explicit Staging(ArtifactFiles& f) : files(f) {}

  ArtifactFiles& files;
  std::string batch = random_hex(4);
  std::vector<std::string> folders;
  std::set<std::string> keep;

  ~Staging() {
    for (const std::string& f : folders) {
      if (!keep.count(f)) files.remove(f);
    }
  }

  // Writes the run's files (without waiting for the disk: merge_staged does, once) and
  // releases their bytes.
  void write(ImportedRun& run) {
    run.staged_folder = "import-" + run.origin_database.substr(0, 8) + "-" +
                        std::to_string(run.origin_job) + "-" + batch;
    folders.push_back(run.staged_folder);  // named before writing: a failed write leaves nothing
    run.staged_paths = files.write(run.staged_folder, run.result.artifacts, false);
    release(run);
  }

  static void release(ImportedRun& run) {
    for (Artifact& a : run.result.artifacts) {
      a.file_size = a.data.size();
      std::string().swap(a.data);
    }
  }
};

namespace {

bool has_result(sqlite::Database& db, const std::string& identity) {
  auto s = db.prepare("SELECT 1 FROM jobs j JOIN results r ON r.job_id = j.id WHERE j.identity = ?");
  s.bind(1, identity);
  return s.step();
}

[[noreturn]] void refuse(const std::string& field, const std::string& message) {
  throw ApiError(422, field, message);
}

// Provenance that names this database must be true of it; a run of another database must not be
// here already with another scene (import_store.hpp).
void check_provenance(sqlite::Database& w, const ExportFile& f, const std::string& own,
                      std::optional<std::int64_t> own_sweep) {
  auto own_job = w.prepare(
      "SELECT j.identity, r.origin_database IS NULL FROM jobs j JOIN results r ON r.job_id = j.id"
      " WHERE j.id = ?");
  auto in_sweep = w.prepare(
      "SELECT 1 FROM sweep_jobs sj JOIN jobs j ON j.id = sj.job_id"
      " WHERE sj.sweep_id = ? AND j.identity = ?");
  auto claimed = w.prepare(
      "SELECT j.id, j.identity FROM results r JOIN jobs j ON j.id = r.job_id"
      " WHERE r.origin_database = ?1 AND r.origin_job = ?2"
      " UNION ALL SELECT j.id, j.identity FROM result_conflicts c JOIN jobs j ON j.id = c.job_id"
      " WHERE c.origin_database = ?1 AND c.origin_job = ?2 LIMIT 1");
  for (std::size_t i = 0; i < f.runs.size(); ++i) {
    const ImportedRun& run = f.runs[i];
    const std::string path = "runs[" + std::to_string(i) + "]";
    if (own_sweep) {
      in_sweep.reset();
      in_sweep.bind(1, *own_sweep).bind(2, run.job.identity);
      if (!in_sweep.step()) {
        refuse(path, "sweep.origin names this database's sweep " + std::to_string(*own_sweep) +
                         ", which does not hold this run");
      }
    }
    if (run.origin_database == own) {
      own_job.reset();
      own_job.bind(1, run.origin_job);
      if (!own_job.step() || own_job.text(0) != run.job.identity || own_job.int64(1) == 0) {
        refuse(path + ".origin", "names job " + std::to_string(run.origin_job) +
                                     " of this database, which is not this run");
      }
      continue;
    }
    claimed.reset();
    claimed.bind(1, run.origin_database).bind(2, run.origin_job);
    if (claimed.step() && claimed.text(1) != run.job.identity) {
      refuse(path + ".origin", "database " + run.origin_database + "'s job " +
                                   std::to_string(run.origin_job) + " is here already, as job " +
                                   std::to_string(claimed.int64(0)) + ", with another scene");
    }
  }
}

}  // namespace

ImportOutcome ImportStore::import_file(const FileReader& read, const std::string& importer,
                                       Millis now) {
  std::lock_guard one_at_a_time(import_mutex_);
  Staging staging(db_.files);
  std::vector<ImportedRun> runs;
  ExportFile f;
  {
    auto db = db_.readers.take();
    f = read([&](ImportedRun& run) {
      if (has_result(*db, run.job.identity)) {
        Staging::release(run);  // its files are here already
      } else {
        staging.write(run);
      }
      runs.push_back(std::move(run));
    });
  }
  f.runs = std::move(runs);
  ImportOutcome out = merge_staged(f, now, importer, staging);
  f = ExportFile();
  // The parse's many small blocks go back to the system, not only to the heap's free lists.
  ::malloc_trim(0);
  return out;
}

ImportOutcome ImportStore::merge(ExportFile f, Millis now, const std::string& importer) {
  Staging staging(db_.files);
  {
    auto db = db_.readers.take();
    for (ImportedRun& run : f.runs) {
      if (run.staged_folder.empty() && !has_result(*db, run.job.identity)) staging.write(run);
    }
  }
  return merge_staged(f, now, importer, staging);
}

namespace {

// The sweep an import's runs are linked to: the one made for this source sweep before, the
// sweep itself when it was made here (and holds every run of the file: check_provenance), or a
// new imported sweep. Returns its id; created says whether it is new.
std::int64_t merge_sweep(sqlite::Database& w, const ExportFile& f, const std::string& own,
                         Millis now, const std::string& importer, bool& created) {
  const bool ours = f.sweep.origin_database == own;
  auto find_sweep = w.prepare(
      ours ? "SELECT id FROM sweeps WHERE id = ?2 AND origin_database IS NULL"
           : "SELECT id FROM sweeps WHERE origin_database = ?1 AND origin_sweep = ?2");
  find_sweep.bind(1, f.sweep.origin_database).bind(2, f.sweep.origin_sweep);
  const bool found = find_sweep.step();
  if (ours && !found) {
    refuse("sweep.origin.sweep", "names sweep " + std::to_string(f.sweep.origin_sweep) +
                                     " of this database, which has no such sweep");
  }
  check_provenance(w, f, own, ours ? std::optional<std::int64_t>(f.sweep.origin_sweep) : std::nullopt);
  created = !found;
  if (found) return find_sweep.int64(0);
  const json origin = {{"source", json::parse(f.source)},
                       {"source_sweep", f.sweep.source_id},
                       {"created_at", f.sweep.created_at},
                       {"exported_at", f.exported_at},
                       {"imported_at", now},
                       {"imported_by", importer}};
  w.prepare(
       "INSERT INTO sweeps (name, request, priority, created_at, origin_database, origin_sweep,"
       " origin) VALUES (?, ?, ?, ?, ?, ?, ?)")
      .bind(1, f.sweep.name)
      .bind(2, f.sweep.request)
      .bind(3, f.sweep.priority)
      .bind(4, now)
      .bind(5, f.sweep.origin_database)
      .bind(6, f.sweep.origin_sweep)
      .bind(7, origin.dump())
      .run();
  return w.last_insert_rowid();
}

// What merging one run did (import_store.hpp's rule).
enum class Merged { added, filled, identical, conflict, conflict_known };

// Merges runs one by one inside the import's transaction, with its statements prepared once.
class RunMerger {
 public:
  RunMerger(sqlite::Database& w, const std::string& own, const ExportFile& f, Millis now)
      : w_(w), own_(own), f_(f), now_(now) {}

  // The run's job here (found or made) and what happened to its result.
  std::pair<std::int64_t, Merged> merge(const ImportedRun& run) {
    find_.reset();
    find_.bind(1, run.job.identity);
    std::int64_t job_id = 0;
    bool has_result = false;
    std::string state;
    if (find_.step()) {
      job_id = find_.int64(0);
      state = find_.text(1);
      has_result = find_.int64(2) != 0;
    }
    find_.reset();
    if (!has_result && run.staged_folder.empty()) {
      // A result that was here when the files were planned can never leave (results are never
      // deleted), so this is a bug, not a race.
      throw sqlite::Error("import: a job lost its result during the import");
    }
    if (job_id == 0) return {add(run), Merged::added};
    if (!has_result) {
      fill(job_id, run, state);
      return {job_id, Merged::filled};
    }
    return {job_id, compare(job_id, run)};
  }

  // Links the job to the sweep at the run's position; true when the link is new.
  bool link(std::int64_t sweep_id, std::int64_t job_id, std::int64_t position) {
    link_.reset();
    link_.bind(1, sweep_id).bind(2, job_id).bind(3, position).run();
    return w_.changes() > 0;
  }

 private:
  // No job of this identity here: a new succeeded job with the imported result.
  std::int64_t add(const ImportedRun& run) {
    insert_job_.reset();
    insert_job_.bind(1, run.job.identity)
        .bind(2, run.job.scene)
        .bind(3, run.engine_version)
        .bind(4, run.job.S)
        .bind(5, run.job.R)
        .bind(6, run.job.phi)
        .bind(7, run.job.cells_per_unit)
        .bind(8, run.job.eps_end)
        .bind(9, f_.sweep.priority)
        .bind(10, run.attempts)
        .bind(11, run.attempts)
        .bind(12, now_)
        .bind(13, run.worker)
        .bind(14, run.result.eps_reached)
        .bind(15, now_)
        .bind(16, run.started_at)
        .bind(17, run.finished_at)
        .bind(18, run.job.structure)
        .run();
    const std::int64_t job_id = w_.last_insert_rowid();
    insert_imported(w_, job_id, run, run.staged_paths, now_);
    log_event(w_, job_id, now_, "succeeded", static_cast<int>(run.attempts), run.worker,
              provenance_note(run));
    return job_id;
  }

  // A job here without a result (in any state) takes the imported one.
  void fill(std::int64_t job_id, const ImportedRun& run, const std::string& state) {
    fill_job_.reset();
    fill_job_.bind(1, job_id)
        .bind(2, run.worker)
        .bind(3, run.result.eps_reached)
        .bind(4, run.started_at)
        .bind(5, run.finished_at)
        .run();
    insert_imported(w_, job_id, run, run.staged_paths, now_);
    log_event(w_, job_id, now_, "succeeded", static_cast<int>(run.attempts), run.worker,
              provenance_note(run) + " (was " + state + ")");
  }

  // A job here with a result: the same run or the same verdict is identical; another verdict is
  // kept beside the stored one, once per source run.
  Merged compare(std::int64_t job_id, const ImportedRun& run) {
    const ResultRecord& r = run.result;
    stored_.reset();
    stored_.bind(1, job_id);
    stored_.step();
    const Verdict here{stored_.text(0),     stored_.opt_text(1).value_or(""), stored_.opt_text(2),
                       stored_.opt_text(3), stored_.opt_text(4),              stored_.opt_real(5),
                       stored_.opt_real(6), stored_.opt_real(7),              stored_.opt_int64(8)};
    const auto here_db = stored_.opt_text(9);
    const auto here_job = stored_.opt_int64(10);
    stored_.reset();
    const bool same_run = (here_db ? *here_db : own_) == run.origin_database &&
                          (here_db ? here_job.value_or(0) : job_id) == run.origin_job;
    if (same_run || here == verdict_of(r)) return Merged::identical;
    conflict_.reset();
    conflict_.bind(1, job_id)
        .bind(2, run.origin_database)
        .bind(3, run.origin_job)
        .bind(4, r.status)
        .bind(5, r.reason)
        .bind(6, r.cls)
        .bind(7, r.confidence)
        .bind(8, r.runner_up)
        .bind(9, r.n_reflections)
        .bind(10, r.band_speed_ratio)
        .bind(11, r.features)
        .bind(12, r.eps_reached)
        .bind(13, r.source_revision)
        .bind(14, run.worker)
        .bind(15, run.result_created_at)
        .bind(16, now_)
        .bind(17, r.summary)
        .run();
    return w_.changes() > 0 ? Merged::conflict : Merged::conflict_known;
  }

  sqlite::Database& w_;
  const std::string& own_;
  const ExportFile& f_;
  const Millis now_;
  sqlite::Statement find_ = w_.prepare(
      "SELECT j.id, j.state, r.job_id IS NOT NULL FROM jobs j LEFT JOIN results r"
      " ON r.job_id = j.id WHERE j.identity = ?");
  sqlite::Statement insert_job_ = w_.prepare(
      "INSERT INTO jobs (identity, scene, engine_version, S, R, phi, cells_per_unit, eps_end,"
      " state, priority, attempts, max_attempts, run_after, worker, progress_eps, created_at,"
      " started_at, finished_at, structure)"
      " VALUES (?, ?, ?, ?, ?, ?, ?, ?, 'succeeded', ?, ?, max(?, 3), ?, ?, ?, ?, ?, ?, ?)");
  sqlite::Statement fill_job_ = w_.prepare(
      "UPDATE jobs SET state = 'succeeded', lease_token = NULL, lease_deadline = NULL,"
      " worker = ?2, progress_eps = ?3, started_at = ?4, finished_at = ?5"
      " WHERE id = ?1 AND state <> 'succeeded'");
  sqlite::Statement stored_ = w_.prepare(
      "SELECT status, reason, class, runner_up, features, confidence, band_speed_ratio,"
      " eps_reached, n_reflections, origin_database, origin_job FROM results WHERE job_id = ?");
  sqlite::Statement conflict_ = w_.prepare(
      "INSERT OR IGNORE INTO result_conflicts (job_id, origin_database, origin_job, status,"
      " reason, class, confidence, runner_up, n_reflections, band_speed_ratio, features,"
      " eps_reached, source_revision, worker, created_at, imported_at, summary)"
      " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  sqlite::Statement link_ = w_.prepare(
      "INSERT OR IGNORE INTO sweep_jobs (sweep_id, job_id, position) VALUES (?, ?, ?)");
};

}  // namespace

// The merge in one transaction: the sweep, then each run (its job, its result, its link to the
// sweep, its human label); a merge that changes nothing rolls back.
ImportOutcome ImportStore::merge_staged(const ExportFile& f, Millis now,
                                        const std::string& importer, Staging& staging) {
  const std::string own = database_id();
  db_.files.wait_synced();  // the staged files are on disk before a commit names them
  std::unique_lock lock(db_.write_mutex);
  sqlite::Transaction tx(db_.writer);
  sqlite::Database& w = db_.writer;
  ImportOutcome out;
  out.runs = static_cast<std::int64_t>(f.runs.size());
  out.sweep_id = merge_sweep(w, f, own, now, importer, out.sweep_created);

  RunMerger merger(w, own, f, now);
  for (const ImportedRun& run : f.runs) {
    const auto [job_id, merged] = merger.merge(run);
    switch (merged) {
      case Merged::added: ++out.added; break;
      case Merged::filled: ++out.filled, out.filled_jobs.push_back(job_id); break;
      case Merged::identical: ++out.identical; break;
      case Merged::conflict: ++out.conflicts; break;
      case Merged::conflict_known: ++out.conflicts_known; break;
    }
    if (merged == Merged::added || merged == Merged::filled) staging.keep.insert(run.staged_folder);
    if (merger.link(out.sweep_id, job_id, run.position)) ++out.linked;
    if (run.human_label &&
        LabelStore::import_label(w, job_id, *run.human_label,
                                 "imported from database " + f.source_database, importer, now)) {
      ++out.labels;
    }
  }
  if (!out.changed()) return out;  // the transaction rolls back: nothing was written
  tx.commit();
  db_.wait_durable(lock);
  return out;
}

std::vector<std::string> ImportStore::conflicts(std::int64_t job_id) {
  auto db = db_.readers.take();
  sqlite::ReadTransaction read(*db);
  auto s = db->prepare(
      "SELECT json_object('database', origin_database, 'job', origin_job, 'status', status,"
      " 'reason', reason, 'class', class, 'confidence', confidence, 'runner_up', runner_up,"
      " 'n_reflections', n_reflections, 'band_speed_ratio', band_speed_ratio,"
      " 'eps_reached', eps_reached, 'source_revision', source_revision, 'worker', worker,"
      " 'created_at', created_at, 'imported_at', imported_at)"
      " FROM result_conflicts WHERE job_id = ? ORDER BY id");
  s.bind(1, job_id);
  std::vector<std::string> out;
  while (s.step()) out.push_back(s.text(0));
  return out;
}

}  // namespace compaction::server
