-- 0001: sweeps, jobs (the queue), results, artifacts and the job event log.
-- Applied once by the server at start and recorded in schema_migrations; never edit it once
-- applied: add 0002_*.sql instead. Times are integer milliseconds since the Unix epoch.

CREATE TABLE sweeps (
  id           INTEGER PRIMARY KEY,
  name         TEXT    NOT NULL CHECK (length(name) BETWEEN 1 AND 200),
  request      TEXT    NOT NULL,               -- the accepted request body (JSON)
  priority     INTEGER NOT NULL DEFAULT 0,     -- higher runs first
  created_at   INTEGER NOT NULL,
  cancelled_at INTEGER                         -- set once by a cancel
);

-- One row per distinct computation: identical parameters (canonical scene JSON + engine
-- version) are computed once and shared by every sweep that contains them.
CREATE TABLE jobs (
  id             INTEGER PRIMARY KEY,
  identity       TEXT    NOT NULL UNIQUE,      -- engine_version '|' canonical scene JSON
  scene          TEXT    NOT NULL,             -- canonical JSON of SceneParams (threads = 1)
  engine_version TEXT    NOT NULL,
  S              REAL    NOT NULL,
  R              REAL    NOT NULL,
  phi            REAL    NOT NULL,
  cells_per_unit INTEGER NOT NULL,
  eps_end        REAL    NOT NULL,
  state          TEXT    NOT NULL DEFAULT 'queued'
                 CHECK (state IN ('queued', 'running', 'succeeded', 'failed', 'cancelled')),
  priority       INTEGER NOT NULL DEFAULT 0,
  attempts       INTEGER NOT NULL DEFAULT 0 CHECK (attempts >= 0),
  max_attempts   INTEGER NOT NULL DEFAULT 3 CHECK (max_attempts BETWEEN 1 AND 100),
  run_after      INTEGER NOT NULL,             -- not leased before this time (retry backoff)
  lease_token    TEXT,
  lease_deadline INTEGER,
  worker         TEXT,                         -- last worker that leased it
  progress_eps   REAL,                         -- imposed strain reached (heartbeats)
  created_at     INTEGER NOT NULL,
  started_at     INTEGER,                      -- last lease
  heartbeat_at   INTEGER,
  finished_at    INTEGER,
  last_error     TEXT,
  -- A lease exists exactly while the job is running.
  CHECK ((state = 'running') = (lease_token IS NOT NULL AND lease_deadline IS NOT NULL)),
  CHECK (state <> 'queued' OR attempts < max_attempts)
);
CREATE INDEX jobs_queue ON jobs (state, priority DESC, run_after, id);
CREATE INDEX jobs_lease ON jobs (state, lease_deadline);
CREATE INDEX jobs_phi ON jobs (phi);

CREATE TABLE sweep_jobs (
  sweep_id INTEGER NOT NULL REFERENCES sweeps (id),
  job_id   INTEGER NOT NULL REFERENCES jobs (id),
  position INTEGER NOT NULL,                   -- order of the point in the request
  PRIMARY KEY (sweep_id, job_id)
);
CREATE INDEX sweep_jobs_job ON sweep_jobs (job_id);

-- At most one result per job (the primary key): a result is never overwritten.
CREATE TABLE results (
  job_id           INTEGER PRIMARY KEY REFERENCES jobs (id),
  status           TEXT    NOT NULL CHECK (status IN ('ok', 'unstable')),
  reason           TEXT    NOT NULL DEFAULT '',
  scene            TEXT    NOT NULL,           -- the parameters the run used
  engine_version   TEXT    NOT NULL,
  source_revision  TEXT    NOT NULL,
  class            TEXT    CHECK (class IS NULL OR class IN ('a', 'b', 'c', 'd', 'e', 'f')),
  confidence       REAL,
  runner_up        TEXT,
  n_reflections    INTEGER,
  band_speed_ratio REAL,
  features         TEXT,                       -- JSON object of the classifier's features
  eps_reached      REAL,
  wall_seconds     REAL,
  summary          TEXT    NOT NULL,           -- summary.json as uploaded
  worker           TEXT    NOT NULL,
  created_at       INTEGER NOT NULL
);

CREATE TABLE artifacts (
  job_id       INTEGER NOT NULL REFERENCES results (job_id),
  name         TEXT    NOT NULL CHECK (length(name) BETWEEN 1 AND 100),
  content_type TEXT    NOT NULL,
  size         INTEGER NOT NULL,
  data         BLOB    NOT NULL,
  PRIMARY KEY (job_id, name)
);

-- What happened to a job and when: leases, heartbeats are not logged, failures with reasons.
CREATE TABLE job_events (
  id      INTEGER PRIMARY KEY,
  job_id  INTEGER NOT NULL REFERENCES jobs (id),
  at      INTEGER NOT NULL,
  kind    TEXT    NOT NULL CHECK (kind IN ('queued', 'leased', 'released', 'lease_expired',
                                           'failed', 'retry', 'succeeded', 'cancelled')),
  attempt INTEGER NOT NULL,
  worker  TEXT,
  message TEXT    NOT NULL DEFAULT ''
);
CREATE INDEX job_events_job ON job_events (job_id, id);
CREATE INDEX job_events_kind ON job_events (kind);
