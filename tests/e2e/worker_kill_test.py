"""kill -9 of a worker in the middle of a job: the lease expires, the rescuer requeues the job,
another worker completes it; the job is not lost and its result is stored once."""
import signal
import time

from e2e_lib import STOPPABLE, STOPPABLE_POINT, Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "worker-kill")
env.start_server("--lease-seconds", "2", "--rescue-interval", "0.3")
doomed = env.start_worker("doomed")
sweep = env.submit({"name": "kill", "points": [STOPPABLE_POINT], "numerics": STOPPABLE})
job_id = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"][0]["id"]

def running_with_progress():
    j = env.get("/api/v1/jobs/%d" % job_id)
    return j if j["state"] == "running" and j["worker"] == "doomed" and (j["progress_eps"] or 0) > 0 else None

env.wait_for(running_with_progress, 60, "the job to run on the doomed worker")
doomed.send_signal(signal.SIGKILL)
doomed.wait()
killed_at = time.time()

rescuer = env.start_worker("rescuer")
done = env.wait_sweep_done(sweep["id"], 120)
check(done["counts"]["succeeded"] == 1, "the job succeeded after the kill: %s" % done["counts"])
job = env.get("/api/v1/jobs/%d" % job_id)
check(job["result"]["worker"] == "rescuer", "the rescuer completed it, not %s" % job["result"]["worker"])
check(job["attempts"] == 2, "two attempts, got %d" % job["attempts"])
kinds = [e["kind"] for e in job["events"]]
check(kinds.count("lease_expired") == 1 and kinds.count("succeeded") == 1, "events: %s" % kinds)
check(env.query("SELECT count(*) FROM results WHERE job_id = ?", job_id) == [(1,)], "one result")
check(env.query("SELECT count(*) FROM jobs") == [(1,)], "no duplicate job")
metrics = env.get_bytes("/metrics")[1].decode()
check("compaction_lease_expiries_total 1" in metrics, "metrics count the expiry")
check(stop(rescuer) == 0, "the rescuer exits 0 on SIGTERM")
print("ok (job completed %.1f s after the kill)" % (time.time() - killed_at))
