-- 0009: the band's early-stage speeds as columns of the phase map, beside those of 0008: c_b/V of
-- the band's middle and of its leading edge over its first leg in the column's upper half, read
-- from the velocity map (docs/classifier.md, band_speed_early and band_speed_lead).
-- Never edit once applied: add 0010_*.sql instead.

-- A number, or NULL when the key is absent, null or not a number (results stored before the
-- classifier had these features read NULL), written by insert_result (server/queue_store.cpp)
-- with the same rule as this backfill.
ALTER TABLE results ADD COLUMN band_speed_early REAL;
ALTER TABLE results ADD COLUMN band_speed_early_error REAL;
ALTER TABLE results ADD COLUMN band_speed_lead REAL;
ALTER TABLE results ADD COLUMN band_speed_lead_error REAL;
UPDATE results SET
  band_speed_early = CASE WHEN json_type(features, '$.band_speed_early') IN ('real', 'integer')
                          THEN json_extract(features, '$.band_speed_early') END,
  band_speed_early_error =
      CASE WHEN json_type(features, '$.band_speed_early_error') IN ('real', 'integer')
           THEN json_extract(features, '$.band_speed_early_error') END,
  band_speed_lead = CASE WHEN json_type(features, '$.band_speed_lead') IN ('real', 'integer')
                         THEN json_extract(features, '$.band_speed_lead') END,
  band_speed_lead_error =
      CASE WHEN json_type(features, '$.band_speed_lead_error') IN ('real', 'integer')
           THEN json_extract(features, '$.band_speed_lead_error') END;

-- GET /phase-map reads the result's columns from this covering index (migration 0008).
DROP INDEX results_map;
CREATE INDEX results_map ON results (job_id, status, class, confidence, runner_up, n_reflections,
                                     band_speed_ratio, band_speed_error, band_speed_transit,
                                     band_speed_transit_error, band_speed_early,
                                     band_speed_early_error, band_speed_lead,
                                     band_speed_lead_error);
