-- 0010: who changed a label, by the token that made the request; an imported label's importer
-- beside what its source claims; the runs of another database found by their origin.
-- Never edit once applied: add 0011_*.sql instead.

-- The token of the request that set the label here: 'open' (a server without submit tokens),
-- 'submit' (--submit-token), 'submit:NAME' (a named token of --tokens); NULL before 0010.
-- An imported label: imported_at is when the import brought it and token the importer's;
-- set_by and set_at stay what the source claims.
ALTER TABLE human_labels ADD COLUMN token TEXT;
ALTER TABLE human_labels ADD COLUMN imported_at INTEGER;

-- A change's token as above. An imported change: set_by is the importer's token and at the
-- time of the import; claimed_by and claimed_at are the source's person and time.
ALTER TABLE label_audit ADD COLUMN token TEXT;
ALTER TABLE label_audit ADD COLUMN claimed_by TEXT;
ALTER TABLE label_audit ADD COLUMN claimed_at INTEGER;

-- An import refuses a second run that claims an origin run already here (import_store.cpp).
CREATE INDEX results_origin ON results (origin_database, origin_job)
  WHERE origin_database IS NOT NULL;
CREATE INDEX result_conflicts_origin ON result_conflicts (origin_database, origin_job);
