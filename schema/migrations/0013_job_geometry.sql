-- 0013: a job's geometry as a column, so that GET /phase-map draws the runs of one geometry
-- (the 2D pseudo-1D column by default; full2d and the 3D column on request) from its covering
-- index, and a 3D run never sits on the 2D map at its (S, R).
-- Never edit once applied: add 0014_*.sql instead.

-- 'pseudo1d', 'full2d' or 'pseudo1d_3d': the scene's geometry (schema/scene.schema.json; a scene
-- stored without the key is the default, pseudo1d).
ALTER TABLE jobs ADD COLUMN geometry TEXT
  CHECK (geometry IS NULL OR geometry IN ('pseudo1d', 'full2d', 'pseudo1d_3d'));
UPDATE jobs SET geometry = coalesce(json_extract(scene, '$.geometry'), 'pseudo1d');

-- Every job inserted from now on (a sweep's, an adaptive sweep's, an import's) takes its
-- scene's geometry by the same rule, here in its one place.
CREATE TRIGGER jobs_geometry AFTER INSERT ON jobs WHEN new.geometry IS NULL
BEGIN
  UPDATE jobs SET geometry = coalesce(json_extract(new.scene, '$.geometry'), 'pseudo1d')
    WHERE id = new.id;
END;

-- GET /phase-map reads the geometry from the covering index of migrations 0008 and 0011.
DROP INDEX jobs_map;
CREATE INDEX jobs_map ON jobs (phi, S, R, id, state, cells_per_unit, eps_end, progress_eps,
                               structure, point_id, geometry);
