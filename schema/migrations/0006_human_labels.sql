-- 0006: labels set by a person beside the classifier's (docs/service.md, "Human labels").
-- Never edit once applied: add 0007_*.sql instead.

-- The current human label of a job (at most one); the classifier's stays in results.class.
CREATE TABLE human_labels (
  job_id     INTEGER PRIMARY KEY REFERENCES results (job_id),
  label      TEXT    NOT NULL CHECK (label IN ('a', 'b', 'c', 'd', 'e', 'f')),
  reason     TEXT    NOT NULL CHECK (length(reason) BETWEEN 1 AND 2000),
  set_by     TEXT    NOT NULL CHECK (length(set_by) BETWEEN 1 AND 200),
  set_at     INTEGER NOT NULL
);

-- Every change of a human label, never deleted: who set or cleared which label, why and when.
-- 'imported': the label came with an import (set_by is the source's person, reason says so).
CREATE TABLE label_audit (
  id             INTEGER PRIMARY KEY,
  job_id         INTEGER NOT NULL REFERENCES jobs (id),
  action         TEXT    NOT NULL CHECK (action IN ('set', 'cleared', 'imported')),
  label          TEXT    CHECK (label IS NULL OR label IN ('a', 'b', 'c', 'd', 'e', 'f')),
  previous_label TEXT    CHECK (previous_label IS NULL OR previous_label IN ('a', 'b', 'c', 'd', 'e', 'f')),
  classifier_label TEXT,                     -- results.class when the change was made
  reason         TEXT    NOT NULL,
  set_by         TEXT    NOT NULL,
  at             INTEGER NOT NULL
);
CREATE INDEX label_audit_job ON label_audit (job_id, id);
