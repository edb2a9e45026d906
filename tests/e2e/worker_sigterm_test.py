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


def children(pid):
    with open("/proc/%d/task/%d/children" % (pid, pid)) as f:
        return [int(c) for c in f.read().split()]


# The worker alone signalled, then (as Slurm's process tracking signals every process of a job)
# the worker and the runner it started for --version.
for name, tree in [("starting", False), ("starting-tree", True)]:
    starting = env.start_worker(name, "--runner", slow)
    time.sleep(1)  # the worker runs, waiting for its runner's version
    check(starting.poll() is None, "the starting worker is still waiting for its runner's version")
    runner = children(starting.pid)
    check(len(runner) == 1, "the worker runs one child, the runner asked its version: %s" % runner)
    starting.send_signal(signal.SIGTERM)
    if tree:
        os.kill(runner[0], signal.SIGTERM)
    check(starting.wait(timeout=15) == 0, "a worker SIGTERMed while it starts exits 0 (%s)" % name)
    said = env.log("worker-" + name)
    check("stopped by signal" in said and "never answered" not in said and "--runner" not in said,
          "it says it was stopped, not that the server never answered: %s" % said[-500:])
print("ok (stopped in %.2f s)" % stop_seconds)
