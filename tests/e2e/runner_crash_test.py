"""A runner that crashes (SIGSEGV) on every job: the worker survives, each crash is reported
with its reason, retried with backoff up to max_attempts, and then the job stays failed."""
import os

from e2e_lib import Env, TINY, bin_dir_from_args, check, stop

here = os.path.dirname(os.path.abspath(__file__))
env = Env(bin_dir_from_args(), "runner-crash")
env.start_server("--retry-backoff", "0.2")
os.environ["COMPACTION_REAL_RUNNER"] = os.path.join(env.bin, "compaction-run")  # its --version
w = env.start_worker("crashy", "--runner", os.path.join(here, "crashing_runner.sh"))
sweep = env.submit({"name": "crash", "points": [{"S": 0.05, "R": 1e-3, "phi": 0.4},
                                               {"S": 0.1, "R": 1e-3, "phi": 0.4}],
                    "numerics": TINY, "max_attempts": 2})
done = env.wait_sweep_done(sweep["id"], 60)
check(done["counts"]["failed"] == 2, "both jobs failed: %s" % done["counts"])
for job in env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"]:
    detail = env.get("/api/v1/jobs/%d" % job["id"])
    check(detail["attempts"] == 2, "two attempts")
    check("signal 11" in detail["last_error"], "the reason names the crash: %s" % detail["last_error"])
    kinds = [e["kind"] for e in detail["events"]]
    check(kinds == ["leased", "retry", "leased", "failed"], "events: %s" % kinds)
    check(detail["result"] is None, "no result")
check(w.poll() is None, "the worker carries on after the crashes")
check(stop(w) == 0, "worker exits 0")
print("ok")
