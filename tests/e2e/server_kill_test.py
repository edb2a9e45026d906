"""kill -9 of the server in the middle of a sweep, then a restart on the same database file and
port: every sweep, job and result stored before the kill survives unchanged, the workers carry
on, and the sweep completes with one result per job."""
import glob
import os
import signal
import time

from e2e_lib import Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "server-kill")
env.start_server("--lease-seconds", "10", "--rescue-interval", "0.5")
port = env.port
workers = [env.start_worker("w1"), env.start_worker("w2")]
# Eight jobs of about half a second each.
sweep = env.submit({"name": "crash", "S": [0.01, 0.02], "R": [1e-4, 1e-3, 1e-2, 1e-1], "phi": 0.4,
                    "numerics": {"cells_per_unit": 8, "eps_end": 0.03}})
check(sweep["created"]["new"] == 8, "8 jobs")

def some_done():
    c = env.get("/api/v1/sweeps/%d" % sweep["id"])["counts"]
    return c["succeeded"] >= 2
env.wait_for(some_done, 120, "two results")
env.server.send_signal(signal.SIGKILL)
env.server.wait()

stored_jobs = env.query("SELECT id, identity, scene FROM jobs ORDER BY id")
stored_results = env.query("SELECT job_id, status, scene, engine_version, source_revision, summary"
                           " FROM results ORDER BY job_id")
stored_artifacts = env.query("SELECT job_id, name, size FROM artifacts ORDER BY job_id, name")
check(len(stored_jobs) == 8 and 2 <= len(stored_results) < 8, "the kill came mid-sweep")
remaining = 8 - len(stored_results)
time.sleep(1.0)  # the workers meet a dead server for a while

env.start_server("--lease-seconds", "10", "--rescue-interval", "0.5", "--port", str(port))
check(env.port == port, "restarted on the same port")
check(env.query("SELECT id, identity, scene FROM jobs ORDER BY id") == stored_jobs, "jobs survive")
after = env.query("SELECT job_id, status, scene, engine_version, source_revision, summary"
                  " FROM results ORDER BY job_id")
check(after[:len(stored_results)] == stored_results, "results survive unchanged")

done = env.wait_sweep_done(sweep["id"], 180)
check(done["counts"]["succeeded"] == 8, "every job succeeded: %s (%d were left at the kill)"
      % (done["counts"], remaining))
final = env.query("SELECT job_id, status, scene, engine_version, source_revision, summary"
                  " FROM results ORDER BY job_id")
check(len(final) == 8 and len({r[0] for r in final}) == 8, "one result per job")
for r in stored_results:
    check(r in final, "result of job %d unchanged" % r[0])
artifacts = env.query("SELECT job_id, name, size FROM artifacts ORDER BY job_id, name")
for a in stored_artifacts:
    check(a in artifacts, "artifact %s survives" % (a,))
for job_id, name, size in stored_artifacts:
    status, data = env.get_bytes("/api/v1/jobs/%d/artifacts/%s" % (job_id, name))
    check(status == 200 and len(data) == size, "artifact %s of job %d served whole after the restart" % (name, job_id))
migrations = glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                    "schema", "migrations", "*.sql"))
check(env.query("SELECT count(*) FROM schema_migrations") == [(len(migrations),)],
      "each migration applied once")
for w in workers:
    check(w.poll() is None, "the workers survived the server's crash")
    check(stop(w) == 0, "worker exits 0")
check(stop(env.server) == 0, "server exits 0")
print("ok (%d of 8 jobs were left at the kill)" % remaining)
