-- 0004: lease expiries counted by worker.
-- Never edit once applied: add 0005_*.sql instead.

-- The lease rescuer (queue_store.cpp: requeue_expired) counts each expired lease under the
-- worker that held it; the metrics export the workers with the newest expiries
-- (compaction_worker_lease_expiries_total). last_at: the newest expiry's time (ms).
CREATE TABLE worker_lease_expiries (
  worker  TEXT    PRIMARY KEY,
  total   INTEGER NOT NULL CHECK (total >= 0),
  last_at INTEGER NOT NULL
);
