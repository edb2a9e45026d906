-- 0007: checkpoints of runs and the resumes from them (docs/service.md, "Checkpoints").
-- Never edit once applied: add 0008_*.sql instead.

-- The newest checkpoint of a job's run: uploaded by a worker that stops mid-run (before it
-- releases its lease), handed to the next lease, removed when the job succeeds or fails for
-- good. Its bytes live in a file below the checkpoints folder beside the database
-- (<db>.checkpoints/, path relative to it). step and eps: where the run stood.
CREATE TABLE job_checkpoints (
  job_id     INTEGER PRIMARY KEY REFERENCES jobs (id),
  path       TEXT    NOT NULL,
  size       INTEGER NOT NULL CHECK (size > 0),
  step       INTEGER NOT NULL CHECK (step >= 0),
  eps        REAL    NOT NULL CHECK (eps >= 0 AND eps <= 1),
  worker     TEXT    NOT NULL,
  attempt    INTEGER NOT NULL,
  created_at INTEGER NOT NULL
);

-- Every resume of a job's run from a checkpoint, as the worker that went on reported it.
CREATE TABLE job_resumes (
  id      INTEGER PRIMARY KEY,
  job_id  INTEGER NOT NULL REFERENCES jobs (id),
  at      INTEGER NOT NULL,
  worker  TEXT    NOT NULL,
  attempt INTEGER NOT NULL,
  step    INTEGER NOT NULL CHECK (step >= 0),
  eps     REAL    NOT NULL CHECK (eps >= 0 AND eps <= 1)
);
CREATE INDEX job_resumes_job ON job_resumes (job_id, id);

-- The event log learns two kinds: 'checkpoint' (a checkpoint uploaded) and 'resumed' (a run
-- went on from one). SQLite cannot change a CHECK constraint in place: the table is rebuilt
-- with the same rows and ids.
CREATE TABLE job_events_new (
  id      INTEGER PRIMARY KEY,
  job_id  INTEGER NOT NULL REFERENCES jobs (id),
  at      INTEGER NOT NULL,
  kind    TEXT    NOT NULL CHECK (kind IN ('queued', 'leased', 'released', 'lease_expired',
                                           'failed', 'retry', 'succeeded', 'cancelled',
                                           'checkpoint', 'resumed')),
  attempt INTEGER NOT NULL,
  worker  TEXT,
  message TEXT    NOT NULL DEFAULT ''
);
INSERT INTO job_events_new (id, job_id, at, kind, attempt, worker, message)
  SELECT id, job_id, at, kind, attempt, worker, message FROM job_events;
DROP TABLE job_events;
ALTER TABLE job_events_new RENAME TO job_events;
CREATE INDEX job_events_job ON job_events (job_id, id);
CREATE INDEX job_events_kind ON job_events (kind);
