"""SIGTERM to a worker in the middle of a job: the run stops, the lease is released so the job
is queued again at once (the attempt not counted), the worker exits 0, another worker finishes."""
import signal
import time

from e2e_lib import STOPPABLE, STOPPABLE_POINT, Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "worker-sigterm")
env.start_server("--lease-seconds", "300")  # a long lease: only the release can requeue in time
first = env.start_worker("first")
sweep = env.submit({"name": "term", "points": [STOPPABLE_POINT], "numerics": STOPPABLE})
job_id = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"][0]["id"]
env.wait_for(lambda: env.get("/api/v1/jobs/%d" % job_id)["state"] == "running", 60, "the job to run")
t = time.time()
check(stop(first, signal.SIGTERM, timeout=15) == 0, "the worker exits 0 on SIGTERM")
stop_seconds = time.time() - t
check(stop_seconds < 10, "the worker stops promptly (%.1f s)" % stop_seconds)
job = env.get("/api/v1/jobs/%d" % job_id)
check(job["state"] == "queued", "queued again at once, got %s" % job["state"])
check(job["attempts"] == 0, "the released attempt does not count: %d" % job["attempts"])
check([e["kind"] for e in job["events"]][-1] == "released", "a 'released' event")
second = env.start_worker("second")
env.wait_sweep_done(sweep["id"], 120)
job = env.get("/api/v1/jobs/%d" % job_id)
check(job["state"] == "succeeded" and job["result"]["worker"] == "second", "the second worker finished it")
check(stop(second) == 0, "exit 0")
print("ok (stopped in %.2f s)" % stop_seconds)
