-- 0008: the phase map's numbers as columns, so that GET /phase-map reads them without parsing
-- a JSON text per run (measured in bench/results/queue_bench.md).
-- Never edit once applied: add 0009_*.sql instead.

-- The band-speed readings of the classifier's features (a number, or NULL when the key is
-- absent, null or not a number), written by insert_result (server/queue_store.cpp) with the
-- same rule as this backfill.
ALTER TABLE results ADD COLUMN band_speed_error REAL;
ALTER TABLE results ADD COLUMN band_speed_transit REAL;
ALTER TABLE results ADD COLUMN band_speed_transit_error REAL;
UPDATE results SET
  band_speed_error = CASE WHEN json_type(features, '$.band_speed_error') IN ('real', 'integer')
                          THEN json_extract(features, '$.band_speed_error') END,
  band_speed_transit = CASE WHEN json_type(features, '$.band_speed_transit') IN ('real', 'integer')
                            THEN json_extract(features, '$.band_speed_transit') END,
  band_speed_transit_error =
      CASE WHEN json_type(features, '$.band_speed_transit_error') IN ('real', 'integer')
           THEN json_extract(features, '$.band_speed_transit_error') END;

-- The scene's structure ('regular' or 'random'), beside S, R and phi; NULL for a scene that
-- names none (written before structures existed: regular).
ALTER TABLE jobs ADD COLUMN structure TEXT CHECK (structure IS NULL OR structure IN ('regular', 'random'));
UPDATE jobs SET structure = json_extract(scene, '$.structure');

-- What GET /phase-map reads of a job and of its result, in covering indexes: the map of one phi
-- is read from these without the rows (a result row holds its summary, about 3 KB, and a job
-- row its scene and identity), in the order the map is drawn (S, then R). jobs_map starts
-- with phi, so it serves every look-up jobs_phi served.
DROP INDEX jobs_phi;
CREATE INDEX jobs_map ON jobs (phi, S, R, id, state, cells_per_unit, eps_end, progress_eps, structure);
CREATE INDEX results_map ON results (job_id, status, class, confidence, runner_up, n_reflections,
                                     band_speed_ratio, band_speed_error, band_speed_transit,
                                     band_speed_transit_error);
