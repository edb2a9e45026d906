-- 0005: sweeps and results imported from another server's export (docs/service.md, "Merging
-- maps"; schema/sweep-export.md). Never edit once applied: add 0006_*.sql instead.

-- This database's identity: every export names it as the source of the runs computed here, and
-- an import recognises runs, sweeps and conflicts by it. Made once, at random.
CREATE TABLE database_identity (
  singleton  INTEGER PRIMARY KEY CHECK (singleton = 1),
  id         TEXT    NOT NULL CHECK (length(id) = 32),   -- 128 random bits, lower-case hex
  created_at INTEGER NOT NULL
);
INSERT INTO database_identity (singleton, id, created_at)
VALUES (1, lower(hex(randomblob(16))), CAST((julianday('now') - 2440587.5) * 86400000 AS INTEGER));

-- An imported sweep: the database and sweep id it was computed as (NULL for a sweep made here),
-- and the provenance of the import as JSON text (the exporting server, when it was exported and
-- imported). One local sweep per source sweep: a second import of it adds to the same one.
ALTER TABLE sweeps ADD COLUMN origin_database TEXT;
ALTER TABLE sweeps ADD COLUMN origin_sweep INTEGER;
ALTER TABLE sweeps ADD COLUMN origin TEXT;
CREATE UNIQUE INDEX sweeps_origin ON sweeps (origin_database, origin_sweep)
  WHERE origin_database IS NOT NULL;

-- An imported result: the database and job that computed it (NULL for a result computed here)
-- and when it was imported. worker, source_revision and created_at keep the source's values.
ALTER TABLE results ADD COLUMN origin_database TEXT;
ALTER TABLE results ADD COLUMN origin_job INTEGER;
ALTER TABLE results ADD COLUMN imported_at INTEGER;

-- A result of the same computation (scene and engine version) brought by an import that differs
-- from the job's stored result: the stored one stays (a result is never overwritten), this one is
-- kept with its provenance. At most one per job and source run, so importing again adds nothing.
CREATE TABLE result_conflicts (
  id               INTEGER PRIMARY KEY,
  job_id           INTEGER NOT NULL REFERENCES jobs (id),
  origin_database  TEXT    NOT NULL,
  origin_job       INTEGER NOT NULL,
  status           TEXT    NOT NULL CHECK (status IN ('ok', 'unstable')),
  reason           TEXT    NOT NULL DEFAULT '',
  class            TEXT    CHECK (class IS NULL OR class IN ('a', 'b', 'c', 'd', 'e', 'f')),
  confidence       REAL,
  runner_up        TEXT,
  n_reflections    INTEGER,
  band_speed_ratio REAL,
  features         TEXT,
  eps_reached      REAL,
  source_revision  TEXT    NOT NULL,
  worker           TEXT    NOT NULL,
  created_at       INTEGER NOT NULL,   -- when the source stored it
  imported_at      INTEGER NOT NULL,
  summary          TEXT    NOT NULL,
  UNIQUE (job_id, origin_database, origin_job)
);
