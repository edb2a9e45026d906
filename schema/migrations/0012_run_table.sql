-- 0012: the run table of GET /api/v1/jobs (docs/service.md, "The run table"): one narrow row per
-- job with the columns a researcher filters and sorts the runs by, kept by triggers beside the
-- tables that own them. Never edit once applied: add 0013_*.sql instead.
--
-- Why a table of its own: a job's row holds its scene and identity and a result's its summary
-- (about 3 KB), so a filter or an order over a result column read 100 000 wide rows through a
-- join: 0.8 s to sort 100 000 runs by confidence. This table is about 90 bytes a run (9 MB
-- at 100 000): any filter and any order is one scan of it (about 15 ms of CPU at 100 000 runs,
-- measured in bench/results/jobs_table.md), whatever the page's depth. So it has no index per
-- column: the scan costs the same with one, and each index would cost every insert and result.
-- Its rowid is the job's id (the default order and its keyset), point_id has an index (a
-- point's replicates are a few rows), and a sweep's runs are found by sweep_jobs' key.
CREATE TABLE run_rows (
  job_id               INTEGER PRIMARY KEY REFERENCES jobs (id),
  sweep                INTEGER,          -- the first sweep that holds the job (the lowest id)
  state                TEXT    NOT NULL, -- jobs.state
  S                    REAL    NOT NULL,
  R                    REAL    NOT NULL,
  phi                  REAL    NOT NULL,
  cells_per_unit       INTEGER NOT NULL, -- the grid the run got (jobs.cells_per_unit)
  point_id             INTEGER,          -- the point it is a replicate of (migration 0011)
  seed                 INTEGER,
  -- The numerics preset the scene was made from, NULL for numerics of its own:
  -- compaction_preset(scene), the store's function (server/store/run_table.hpp, scene_preset),
  -- defined on the server's connection; a job inserted by another program fails here.
  preset               TEXT,
  -- The result (NULL before one) and where it was computed (NULL: here).
  status               TEXT,
  class                TEXT,
  confidence           REAL,
  runner_up            TEXT,
  n_reflections        INTEGER,
  band_speed_ratio     REAL,
  source_database      TEXT,             -- results.origin_database of an imported result
  source_job           INTEGER,          -- results.origin_job
  human_label          TEXT,             -- human_labels.label
  -- The label that counts: a person's where there is one, else the classifier's
  -- (server/plan/counted_label.hpp).
  label                TEXT GENERATED ALWAYS AS (coalesce(human_label, class)) VIRTUAL
);
CREATE INDEX run_rows_point ON run_rows (point_id);

INSERT INTO run_rows (job_id, sweep, state, S, R, phi, cells_per_unit, point_id, seed, preset,
                      status, class, confidence, runner_up, n_reflections, band_speed_ratio,
                      source_database, source_job, human_label)
  SELECT j.id, (SELECT min(sweep_id) FROM sweep_jobs WHERE job_id = j.id), j.state, j.S, j.R,
         j.phi, j.cells_per_unit, j.point_id, json_extract(j.scene, '$.seed'),
         compaction_preset(j.scene), r.status, r.class, r.confidence, r.runner_up,
         r.n_reflections, r.band_speed_ratio, r.origin_database, r.origin_job, h.label
    FROM jobs j LEFT JOIN results r ON r.job_id = j.id LEFT JOIN human_labels h ON h.job_id = j.id;

-- Each fact is copied from its owner when the owner writes it, by the same rule as the backfill
-- above. A job's S, R, phi, grid and scene never change; its state does, and its point is set
-- right after its insert (jobs_find_point, 0011: whichever of the two triggers runs first, the
-- row gets the point).
CREATE TRIGGER run_rows_job AFTER INSERT ON jobs
BEGIN
  INSERT INTO run_rows (job_id, state, S, R, phi, cells_per_unit, point_id, seed, preset)
    VALUES (new.id, new.state, new.S, new.R, new.phi, new.cells_per_unit,
            (SELECT point_id FROM jobs WHERE id = new.id), json_extract(new.scene, '$.seed'),
            compaction_preset(new.scene));
END;

CREATE TRIGGER run_rows_point AFTER UPDATE OF point_id ON jobs
BEGIN
  UPDATE run_rows SET point_id = new.point_id WHERE job_id = new.id;
END;

CREATE TRIGGER run_rows_state AFTER UPDATE OF state ON jobs WHEN new.state IS NOT old.state
BEGIN
  UPDATE run_rows SET state = new.state WHERE job_id = new.id;
END;

-- sweep_jobs rows are never deleted: the first sweep only gets lower.
CREATE TRIGGER run_rows_sweep AFTER INSERT ON sweep_jobs
BEGIN
  UPDATE run_rows SET sweep = new.sweep_id
    WHERE job_id = new.job_id AND (sweep IS NULL OR sweep > new.sweep_id);
END;

-- A result is written once and never changed (its primary key).
CREATE TRIGGER run_rows_result AFTER INSERT ON results
BEGIN
  UPDATE run_rows SET status = new.status, class = new.class, confidence = new.confidence,
                      runner_up = new.runner_up, n_reflections = new.n_reflections,
                      band_speed_ratio = new.band_speed_ratio,
                      source_database = new.origin_database, source_job = new.origin_job
    WHERE job_id = new.job_id;
END;

CREATE TRIGGER run_rows_label_set AFTER INSERT ON human_labels
BEGIN
  UPDATE run_rows SET human_label = new.label WHERE job_id = new.job_id;
END;

CREATE TRIGGER run_rows_label_changed AFTER UPDATE OF label ON human_labels
BEGIN
  UPDATE run_rows SET human_label = new.label WHERE job_id = new.job_id;
END;

CREATE TRIGGER run_rows_label_cleared AFTER DELETE ON human_labels
BEGIN
  UPDATE run_rows SET human_label = NULL WHERE job_id = old.job_id;
END;
