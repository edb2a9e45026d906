"""End to end: a server and two workers on loopback run a small grid sweep; every job succeeds
with its result (parameters, engine version, source revision, label when the runner classifies),
the phase map and the exports list them, artifacts download, and a second sweep reuses them."""
import signal

from e2e_lib import Env, TINY, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "sweep")
env.start_server()
w1 = env.start_worker("w1")
w2 = env.start_worker("w2")

sweep = env.submit({"name": "grid", "S": {"min": 0.05, "max": 0.1, "n": 2, "scale": "log"},
                    "R": [1e-3, 1e-2], "phi": 0.4, "numerics": TINY})
check(sweep["created"]["new"] == 4, "4 new jobs: %s" % sweep)
done = env.wait_sweep_done(sweep["id"], 120)
check(done["counts"]["succeeded"] == 4, "every job succeeded: %s" % done["counts"])
check(done["state"] == "done", "sweep state: %s" % done["state"])

jobs = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"]
check(len(jobs) == 4, "4 jobs listed")
for job in jobs:
    detail = env.get("/api/v1/jobs/%d" % job["id"])
    r = detail["result"]
    check(r is not None, "job %d has a result" % job["id"])
    check(r["status"] in ("ok", "unstable"), "status %s" % r["status"])
    check(r["engine_version"] and r["source_revision"], "versions stored beside the result")
    check(r["summary"]["params"]["S"] == job["S"], "the summary's parameters are the job's")
    check(detail["scene"]["cells_per_unit"] == 6 and detail["scene"]["eps_end"] == 0.03,
          "the stored scene carries the numerics")
    classification = r["summary"].get("classification")
    if classification is not None:  # the runner labels runs (issue 3): the label must be stored
        # a-f, or null when the run shows no pattern that fits (features.label "unclassified")
        check(r["class"] == classification["class"] and (r["class"] is None or r["class"] in "abcdef"),
              "job %d label %s" % (job["id"], r["class"]))
        check("confidence" in classification and "features" in classification,
              "job %d classification carries confidence and features" % job["id"])
    else:
        check(r["class"] is None, "no label invented when the runner gives none")
    check(detail["attempts"] == 1, "one attempt")
    names = {a["name"] for a in env.get("/api/v1/jobs/%d/artifacts" % job["id"])["artifacts"]}
    for required in ("summary.json", "frames.csv", "spacetime.npy", "spacetime.png"):
        check(required in names, "artifact %s of job %d (have %s)" % (required, job["id"], names))

status, npy = env.get_bytes("/api/v1/jobs/%d/artifacts/spacetime.npy" % jobs[0]["id"])
check(status == 200 and npy.startswith(b"\x93NUMPY"),
      "spacetime.npy downloads as a .npy file")

points = env.get("/api/v1/phase-map?phi=0.4")["points"]
check(sorted(p["job_id"] for p in points) == sorted(j["id"] for j in jobs), "phase map lists the jobs")
check(all(p["state"] == "succeeded" and p["status"] in ("ok", "unstable") for p in points),
      "phase map states")
check(env.get("/api/v1/phase-map?phi=0.5")["points"] == [], "nothing at phi = 0.5")

export = env.get("/api/v1/sweeps/%d/export?format=json" % sweep["id"])
check(len(export["jobs"]) == 4 and all(j["result"] for j in export["jobs"]), "JSON export")
status, csv = env.request("GET", "/api/v1/sweeps/%d/export?format=csv" % sweep["id"])
lines = csv.strip().split("\n")
check(status == 200 and len(lines) == 5 and lines[0].startswith("job_id,S,R,phi"), "CSV export: %s" % lines[:2])

# A second sweep sharing two points reuses their results and computes only the new one.
again = env.submit({"name": "again", "points": [{"S": 0.05, "R": 1e-3, "phi": 0.4},
                                                {"S": 0.1, "R": 1e-2, "phi": 0.4},
                                                {"S": 0.07, "R": 1e-3, "phi": 0.4}],
                    "numerics": TINY})
check(again["created"]["reused"] == 2 and again["created"]["new"] == 1, "reuse: %s" % again["created"])
env.wait_sweep_done(again["id"], 60)
check(env.query("SELECT count(*), count(DISTINCT job_id) FROM results") == [(5, 5)],
      "five computations, one result each")

metrics = env.get_bytes("/metrics")[1].decode()
check('compaction_jobs{state="succeeded"} 5' in metrics, "metrics count the jobs")

for w in (w1, w2):
    check(stop(w, signal.SIGTERM) == 0, "a worker exits 0 on SIGTERM")
check(stop(env.server, signal.SIGTERM) == 0, "the server exits 0 on SIGTERM")
print("ok")
