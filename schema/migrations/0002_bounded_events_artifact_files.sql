-- 0002: a bounded event log and artifacts stored as files.
-- Never edit once applied: add 0003_*.sql instead.

-- The event log keeps the newest events of each job (job_store.cpp: max_events_per_job); the
-- dropped ones are counted per job, and every event ever logged is counted by kind, so the
-- totals (the metrics' counters) never fall when old rows go.
ALTER TABLE jobs ADD COLUMN events_dropped INTEGER NOT NULL DEFAULT 0 CHECK (events_dropped >= 0);

CREATE TABLE event_totals (
  kind  TEXT    PRIMARY KEY,
  total INTEGER NOT NULL CHECK (total >= 0)
);
INSERT INTO event_totals (kind, total) SELECT kind, count(*) FROM job_events GROUP BY kind;

-- An artifact's bytes live in a file below the artifacts folder beside the database (path,
-- relative to it), written before the result's transaction; data then holds an empty blob.
-- Rows from before this migration keep their bytes in data and have no path.
ALTER TABLE artifacts ADD COLUMN path TEXT;
