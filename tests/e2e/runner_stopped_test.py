"""A runner stopped by a SIGTERM the worker did not send (a batch system signals every process of
a job, the runner too): the runner writes its checkpoint, the worker uploads it and gives the
lease back, the attempt not counted and no failure recorded, and carries on: it leases the job
again and goes on from the checkpoint."""
import os
import signal

from e2e_lib import Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "runner-stopped")
env.start_server("--lease-seconds", "300")  # a long lease: only the release can requeue in time
w = env.start_worker("w")
sweep = env.submit({"name": "stopped", "points": [{"S": 0.003, "R": 1e-3, "phi": 0.4}],
                    "numerics": {"cells_per_unit": 8, "eps_end": 0.2}})  # ~6 s optimised
job_id = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"][0]["id"]
env.wait_for(lambda: env.get("/api/v1/jobs/%d" % job_id)["state"] == "running", 60, "the job to run")


def runner_pids():
    """The worker's compaction-run children, from /proc."""
    pids = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/stat" % pid) as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                argv0 = f.read().split(b"\0")[0]
        except (OSError, ValueError, IndexError):
            continue
        if ppid == w.pid and argv0.endswith(b"compaction-run"):
            pids.append(int(pid))
    return pids


runners = env.wait_for(runner_pids, 30, "the runner process")
check(len(runners) == 1, "one runner: %s" % runners)
# The signal goes to a runner that is computing (its first frame reported): one signalled while
# it starts, before its handler is installed, dies without a checkpoint (the worker then gives
# the job back and the next lease starts afresh, which is not what this test is about).
env.wait_for(lambda: (env.get("/api/v1/jobs/%d" % job_id).get("progress_eps") or 0) > 0, 60,
             "the runner's first progress")
os.kill(runners[0], signal.SIGTERM)


def kinds():
    return [e["kind"] for e in env.get("/api/v1/jobs/%d" % job_id)["events"]]


env.wait_for(lambda: len(kinds()) >= 5, 60, "the job to be given back, leased again and resumed")
check(kinds()[:5] == ["leased", "checkpoint", "released", "leased", "resumed"],
      "checkpoint uploaded, given back, then leased again and resumed; events %s" % kinds())
job = env.get("/api/v1/jobs/%d" % job_id)
check(job["attempts"] <= 1 and job["last_error"] is None,
      "the stopped run is no failed attempt: attempts %d, last_error %s" % (job["attempts"], job["last_error"]))
check(w.poll() is None, "the worker carries on")
check(stop(w) == 0, "the worker exits 0 on SIGTERM")
print("ok")
