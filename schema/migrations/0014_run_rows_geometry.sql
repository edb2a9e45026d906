-- 0014: the run table gets each job's geometry (migration 0013's column), so GET /api/v1/jobs
-- filters and sorts by it and gives the cells across a strut by the geometry's rule (the square
-- hole's in 2D, the cubic hole's in 3D). Never edit once applied: add 0015_*.sql instead.

ALTER TABLE run_rows ADD COLUMN geometry TEXT;
UPDATE run_rows SET geometry = (SELECT geometry FROM jobs WHERE id = run_rows.job_id);

-- A job's geometry is set by jobs_geometry (0013) right after its insert: whichever of that
-- trigger and run_rows_job runs first, the row gets it (as its point, 0011 and 0012).
DROP TRIGGER run_rows_job;
CREATE TRIGGER run_rows_job AFTER INSERT ON jobs
BEGIN
  INSERT INTO run_rows (job_id, state, S, R, phi, cells_per_unit, point_id, seed, preset, geometry)
    VALUES (new.id, new.state, new.S, new.R, new.phi, new.cells_per_unit,
            (SELECT point_id FROM jobs WHERE id = new.id), json_extract(new.scene, '$.seed'),
            compaction_preset(new.scene), (SELECT geometry FROM jobs WHERE id = new.id));
END;

CREATE TRIGGER run_rows_geometry AFTER UPDATE OF geometry ON jobs
BEGIN
  UPDATE run_rows SET geometry = new.geometry WHERE job_id = new.id;
END;
