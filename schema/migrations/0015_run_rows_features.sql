-- 0015: the run table gets the classifier's numeric features and each run's strain reached and
-- wall time, so GET /api/v1/jobs filters, sorts and plots by them (the Plots page offers every
-- numeric column: the deflection before yield against R, the coherence against S). A feature is
-- a number, or NULL when the result's features lack it, hold null (NaN: not measured) or hold
-- something else, by the rule of the phase map's band-speed columns (0008). The rows grow by
-- these columns; a scan stays one pass over the table (its size and cost at 100 000 runs:
-- bench/results/jobs_table.md). Never edit once applied: add 0016_*.sql instead.

ALTER TABLE run_rows ADD COLUMN first_reflection_eps REAL;
ALTER TABLE run_rows ADD COLUMN speed_excess REAL;
ALTER TABLE run_rows ADD COLUMN arrival_eps REAL;
ALTER TABLE run_rows ADD COLUMN coherence REAL;
ALTER TABLE run_rows ADD COLUMN peak_jump REAL;
ALTER TABLE run_rows ADD COLUMN stress_ratio REAL;
ALTER TABLE run_rows ADD COLUMN undulation_share REAL;
ALTER TABLE run_rows ADD COLUMN deflection_growth REAL;
ALTER TABLE run_rows ADD COLUMN deflection_before_yield REAL;
ALTER TABLE run_rows ADD COLUMN n_fronts INTEGER;
ALTER TABLE run_rows ADD COLUMN band_turns INTEGER;
ALTER TABLE run_rows ADD COLUMN band_speed_error REAL;
ALTER TABLE run_rows ADD COLUMN band_speed_early REAL;
ALTER TABLE run_rows ADD COLUMN band_speed_lead REAL;
ALTER TABLE run_rows ADD COLUMN bottom_speed_ratio REAL;
ALTER TABLE run_rows ADD COLUMN top_stress_undulation REAL;
ALTER TABLE run_rows ADD COLUMN stress_drop REAL;
ALTER TABLE run_rows ADD COLUMN eps_first_yield REAL;
ALTER TABLE run_rows ADD COLUMN eps_reached REAL;
ALTER TABLE run_rows ADD COLUMN wall_seconds REAL;

UPDATE run_rows SET
  first_reflection_eps = CASE WHEN json_type(r.features, '$.first_reflection_eps') IN ('real', 'integer')
                           THEN json_extract(r.features, '$.first_reflection_eps') END,
  speed_excess = CASE WHEN json_type(r.features, '$.speed_excess') IN ('real', 'integer')
                   THEN json_extract(r.features, '$.speed_excess') END,
  arrival_eps = CASE WHEN json_type(r.features, '$.arrival_eps') IN ('real', 'integer')
                  THEN json_extract(r.features, '$.arrival_eps') END,
  coherence = CASE WHEN json_type(r.features, '$.coherence') IN ('real', 'integer')
                THEN json_extract(r.features, '$.coherence') END,
  peak_jump = CASE WHEN json_type(r.features, '$.peak_jump') IN ('real', 'integer')
                THEN json_extract(r.features, '$.peak_jump') END,
  stress_ratio = CASE WHEN json_type(r.features, '$.stress_ratio') IN ('real', 'integer')
                   THEN json_extract(r.features, '$.stress_ratio') END,
  undulation_share = CASE WHEN json_type(r.features, '$.undulation_share') IN ('real', 'integer')
                       THEN json_extract(r.features, '$.undulation_share') END,
  deflection_growth = CASE WHEN json_type(r.features, '$.deflection_growth') IN ('real', 'integer')
                        THEN json_extract(r.features, '$.deflection_growth') END,
  deflection_before_yield = CASE WHEN json_type(r.features, '$.deflection_before_yield') IN ('real', 'integer')
                              THEN json_extract(r.features, '$.deflection_before_yield') END,
  n_fronts = CASE WHEN json_type(r.features, '$.n_fronts') IN ('real', 'integer')
               THEN json_extract(r.features, '$.n_fronts') END,
  band_turns = CASE WHEN json_type(r.features, '$.band_turns') IN ('real', 'integer')
                 THEN json_extract(r.features, '$.band_turns') END,
  band_speed_error = CASE WHEN json_type(r.features, '$.band_speed_error') IN ('real', 'integer')
                       THEN json_extract(r.features, '$.band_speed_error') END,
  band_speed_early = CASE WHEN json_type(r.features, '$.band_speed_early') IN ('real', 'integer')
                       THEN json_extract(r.features, '$.band_speed_early') END,
  band_speed_lead = CASE WHEN json_type(r.features, '$.band_speed_lead') IN ('real', 'integer')
                      THEN json_extract(r.features, '$.band_speed_lead') END,
  bottom_speed_ratio = CASE WHEN json_type(r.features, '$.bottom_speed_ratio') IN ('real', 'integer')
                         THEN json_extract(r.features, '$.bottom_speed_ratio') END,
  top_stress_undulation = CASE WHEN json_type(r.features, '$.top_stress_undulation') IN ('real', 'integer')
                            THEN json_extract(r.features, '$.top_stress_undulation') END,
  stress_drop = CASE WHEN json_type(r.features, '$.stress_drop') IN ('real', 'integer')
                  THEN json_extract(r.features, '$.stress_drop') END,
  eps_first_yield = CASE WHEN json_type(r.features, '$.eps_first_yield') IN ('real', 'integer')
                      THEN json_extract(r.features, '$.eps_first_yield') END,
  eps_reached = r.eps_reached,
  wall_seconds = r.wall_seconds
  FROM results r WHERE r.job_id = run_rows.job_id;

-- A result is written once and never changed (its primary key): its row takes the features as
-- the backfill above reads them.
DROP TRIGGER run_rows_result;
CREATE TRIGGER run_rows_result AFTER INSERT ON results
BEGIN
  UPDATE run_rows SET status = new.status, class = new.class, confidence = new.confidence,
                      runner_up = new.runner_up, n_reflections = new.n_reflections,
                      band_speed_ratio = new.band_speed_ratio,
                      source_database = new.origin_database, source_job = new.origin_job,
                      eps_reached = new.eps_reached, wall_seconds = new.wall_seconds,
                      first_reflection_eps = CASE WHEN json_type(new.features, '$.first_reflection_eps') IN ('real', 'integer')
                                             THEN json_extract(new.features, '$.first_reflection_eps') END,
                      speed_excess = CASE WHEN json_type(new.features, '$.speed_excess') IN ('real', 'integer')
                                     THEN json_extract(new.features, '$.speed_excess') END,
                      arrival_eps = CASE WHEN json_type(new.features, '$.arrival_eps') IN ('real', 'integer')
                                    THEN json_extract(new.features, '$.arrival_eps') END,
                      coherence = CASE WHEN json_type(new.features, '$.coherence') IN ('real', 'integer')
                                  THEN json_extract(new.features, '$.coherence') END,
                      peak_jump = CASE WHEN json_type(new.features, '$.peak_jump') IN ('real', 'integer')
                                  THEN json_extract(new.features, '$.peak_jump') END,
                      stress_ratio = CASE WHEN json_type(new.features, '$.stress_ratio') IN ('real', 'integer')
                                     THEN json_extract(new.features, '$.stress_ratio') END,
                      undulation_share = CASE WHEN json_type(new.features, '$.undulation_share') IN ('real', 'integer')
                                         THEN json_extract(new.features, '$.undulation_share') END,
                      deflection_growth = CASE WHEN json_type(new.features, '$.deflection_growth') IN ('real', 'integer')
                                          THEN json_extract(new.features, '$.deflection_growth') END,
                      deflection_before_yield = CASE WHEN json_type(new.features, '$.deflection_before_yield') IN ('real', 'integer')
                                                THEN json_extract(new.features, '$.deflection_before_yield') END,
                      n_fronts = CASE WHEN json_type(new.features, '$.n_fronts') IN ('real', 'integer')
                                 THEN json_extract(new.features, '$.n_fronts') END,
                      band_turns = CASE WHEN json_type(new.features, '$.band_turns') IN ('real', 'integer')
                                   THEN json_extract(new.features, '$.band_turns') END,
                      band_speed_error = CASE WHEN json_type(new.features, '$.band_speed_error') IN ('real', 'integer')
                                         THEN json_extract(new.features, '$.band_speed_error') END,
                      band_speed_early = CASE WHEN json_type(new.features, '$.band_speed_early') IN ('real', 'integer')
                                         THEN json_extract(new.features, '$.band_speed_early') END,
                      band_speed_lead = CASE WHEN json_type(new.features, '$.band_speed_lead') IN ('real', 'integer')
                                        THEN json_extract(new.features, '$.band_speed_lead') END,
                      bottom_speed_ratio = CASE WHEN json_type(new.features, '$.bottom_speed_ratio') IN ('real', 'integer')
                                           THEN json_extract(new.features, '$.bottom_speed_ratio') END,
                      top_stress_undulation = CASE WHEN json_type(new.features, '$.top_stress_undulation') IN ('real', 'integer')
                                              THEN json_extract(new.features, '$.top_stress_undulation') END,
                      stress_drop = CASE WHEN json_type(new.features, '$.stress_drop') IN ('real', 'integer')
                                    THEN json_extract(new.features, '$.stress_drop') END,
                      eps_first_yield = CASE WHEN json_type(new.features, '$.eps_first_yield') IN ('real', 'integer')
                                        THEN json_extract(new.features, '$.eps_first_yield') END
    WHERE job_id = new.job_id;
END;
