"""End to end: a worker asks for its next job with each result (next_lease), so the job that
follows a result is leased in the upload's transaction, and a worker that stops after this job
(--max-jobs) asks for none: a real server and worker on loopback, three jobs.
  - a worker with --max-jobs 2 runs two jobs and exits 0 after one request to POST /leases (the
    server's debug log of requests): its first upload leased the second job (in the same
    transaction: the 'leased' event of job 2 has the time of job 1's 'succeeded' event), its
    second upload leased nothing, so the third job is still queued with no attempt;
  - a second worker without the limit runs the third job."""
import os

from e2e_lib import Env, TINY, bin_dir_from_args, check

env = Env(bin_dir_from_args(), "next-lease")
env.start_server("--log-level", "debug")
sweep = env.submit({"name": "three", "S": [0.05, 0.07, 0.09], "R": 1e-3, "phi": 0.4,
                    "numerics": TINY})
check(sweep["created"]["new"] == 3, "3 new jobs: %s" % sweep)

w1 = env.start_worker("w1", "--max-jobs", "2")
check(w1.wait(120) == 0, "the worker with --max-jobs 2 exits 0 after its jobs")
with open(os.path.join(env.dir, "server.log")) as f:
    lease_requests = f.read().count("POST /api/v1/leases -> ")
check(lease_requests == 1, "one lease request for two jobs, %d made" % lease_requests)
jobs = sorted(env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"], key=lambda j: j["id"])
states = [j["state"] for j in jobs]
check(states.count("succeeded") == 2 and states.count("queued") == 1,
      "two jobs done, one still queued: %s" % states)


def events(job_id):
    return env.query("SELECT kind, at, worker FROM job_events WHERE job_id = ? ORDER BY id", job_id)


done = [j for j in jobs if j["state"] == "succeeded"]
first_done = [at for kind, at, _ in events(done[0]["id"]) if kind == "succeeded"][0]
second_leased = [at for kind, at, _ in events(done[1]["id"]) if kind == "leased"][0]
check(second_leased == first_done,
      "the second job was leased in the first one's upload (%d, %d)" % (second_leased, first_done))
waiting = [j for j in jobs if j["state"] == "queued"][0]
check(env.query("SELECT attempts FROM jobs WHERE id = ?", waiting["id"])[0][0] == 0,
      "the last upload leased nothing: the third job has no attempt")
check("leased" not in [kind for kind, _, _ in events(waiting["id"])],
      "the third job was never leased: %s" % events(waiting["id"]))

w2 = env.start_worker("w2")
done = env.wait_sweep_done(sweep["id"], 120)
check(done["counts"]["succeeded"] == 3, "the second worker ran the third job: %s" % done["counts"])
print("worker_next_lease_test: ok")
