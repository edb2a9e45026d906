"""SIGTERM to a worker in the middle of a job: the run stops, the lease is released so the job
is queued again at once (the attempt not counted), the worker exits 0, another worker finishes.
SIGTERM to a worker that is still starting (its runner slow to say its version, as a batch system
may signal right after it started the worker): it exits 0 as well, asking the server nothing."""
import os
import signal
import stat
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

slow = os.path.join(env.dir, "slow_version_runner.sh")
with open(slow, "w") as f:
    f.write('#!/bin/sh\nif [ "${1:-}" = "--version" ]; then sleep 3; fi\nexec "%s" "$@"\n'
            % os.path.join(env.bin, "compaction-run"))
os.chmod(slow, os.stat(slow).st_mode | stat.S_IXUSR)
starting = env.start_worker("starting", "--runner", slow)
time.sleep(1)  # the worker runs, waiting for its runner's version
check(starting.poll() is None, "the starting worker is still waiting for its runner's version")
check(stop(starting, signal.SIGTERM, timeout=15) == 0, "a worker SIGTERMed while it starts exits 0")
said = env.log("worker-starting")
check("stopped by signal after 0 job(s)" in said and "never answered" not in said,
      "it says it was stopped, not that the server never answered: %s" % said[-500:])
print("ok (stopped in %.2f s)" % stop_seconds)
