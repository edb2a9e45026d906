-- 0003: an index in the order a lease claims jobs.
-- Never edit once applied: add 0004_*.sql instead.

-- The claim (queue_store.cpp: lease) takes the first queued job of an engine version by
-- priority, then age. jobs_queue (state, priority DESC, run_after, id) holds run_after between
-- priority and id, so SQLite read every queued job of the highest priority and sorted them: a
-- lease cost grew with the queue. This index is in the claim's order; run_after is checked on
-- the rows it walks (jobs waiting for a retry's backoff are few).
CREATE INDEX jobs_claim ON jobs (state, engine_version, priority DESC, id);
DROP INDEX jobs_queue;
