-- 0011: the points of the map. A point is a computation up to its seed: the jobs of one engine
-- version whose scenes differ only by `seed` are replicates of one point (numerics.seeds, or a
-- sweep's replicates: docs/replicates.md), and the map shows the point, with its runs beside it.
-- Never edit once applied: add 0012_*.sql instead.

-- A point's key: the engine version and the job's canonical scene without its seed (the job's
-- identity, server/plan/planner.hpp, but for the seed). Keys are kept once; a job names its
-- point by id, small enough for the phase map's covering index.
CREATE TABLE points (
  id INTEGER PRIMARY KEY,
  key TEXT NOT NULL UNIQUE
);

ALTER TABLE jobs ADD COLUMN point_id INTEGER REFERENCES points (id);

INSERT OR IGNORE INTO points (key)
  SELECT engine_version || '|' || json_remove(scene, '$.seed') FROM jobs ORDER BY id;
UPDATE jobs SET point_id =
  (SELECT p.id FROM points p WHERE p.key = jobs.engine_version || '|' || json_remove(jobs.scene, '$.seed'));

-- Every job inserted from now on (a sweep's, an adaptive sweep's, an import's) finds or makes its
-- point by the same rule, here in its one place.
CREATE TRIGGER jobs_find_point AFTER INSERT ON jobs WHEN new.point_id IS NULL
BEGIN
  INSERT OR IGNORE INTO points (key)
    VALUES (new.engine_version || '|' || json_remove(new.scene, '$.seed'));
  UPDATE jobs SET point_id =
    (SELECT id FROM points WHERE key = new.engine_version || '|' || json_remove(new.scene, '$.seed'))
    WHERE id = new.id;
END;

-- A point's replicates, found from one of them (the run page's siblings).
CREATE INDEX jobs_point ON jobs (point_id);

-- GET /phase-map reads a job's point from the covering index of migration 0008.
DROP INDEX jobs_map;
CREATE INDEX jobs_map ON jobs (phi, S, R, id, state, cells_per_unit, eps_end, progress_eps,
                               structure, point_id);
