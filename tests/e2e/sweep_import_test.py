"""End to end: a map computed in parts. Two servers, each with a real worker, compute their half
of a small sweep at the fast preset (tiny runs); each half is exported
(GET /sweeps/{id}/export?format=archive) and a third server's database imports both files with
`compaction-server --import FILE`. Started on that database, the third server's phase map holds
the union with the labels the workers found, each imported sweep is marked with where it was
computed, the run page's artifacts are there, and a second import of the same file changes
nothing in the database. A truncated file is refused and imports nothing."""
import json
import os
import subprocess

from e2e_lib import Env, bin_dir_from_args, check

bin_dir = bin_dir_from_args()
NUMERICS = {"preset": "fast", "eps_end": 0.03}
POINTS = [{"S": 0.05, "R": 1e-3, "phi": 0.4}, {"S": 0.05, "R": 3e-2, "phi": 0.4},
          {"S": 0.1, "R": 1e-3, "phi": 0.4}, {"S": 0.1, "R": 3e-2, "phi": 0.4}]


def compute_part(name, points):
    env = Env(bin_dir, name)
    env.start_server()
    env.start_worker("w-" + name)
    sweep = env.submit({"name": "map part " + name, "points": points, "numerics": NUMERICS})
    env.wait_sweep_done(sweep["id"], 240)
    status, body = env.get_bytes("/api/v1/sweeps/%d/export?format=archive" % sweep["id"])
    check(status == 200, "export -> %d" % status)
    path = os.path.join(env.dir, "part-%s.export.json" % name)
    with open(path, "wb") as f:
        f.write(body)
    labels = {(p["S"], p["R"]): p["class"] for p in env.get("/api/v1/phase-map?phi=0.4")["points"]}
    print("part %s: %d runs, export %d bytes" % (name, len(labels), len(body)))
    return env, path, labels


part_a, file_a, labels_a = compute_part("a", POINTS[:2])
part_b, file_b, labels_b = compute_part("b", POINTS[1:])  # one point in both parts
for env in (part_a, part_b):
    env.server.terminate()
    env.server.wait()
    for w in env.workers:
        w.terminate()
        w.wait()

merged = Env(bin_dir, "merged")


def run_import(path):
    p = subprocess.run([os.path.join(bin_dir, "compaction-server"), "--db", merged.db, "--import", path],
                       capture_output=True, text=True, timeout=60)
    return p.returncode, p.stdout, p.stderr


def dump():
    return merged.query("SELECT count(*) FROM jobs") + merged.query("SELECT count(*) FROM results") + \
        merged.query("SELECT count(*) FROM sweeps") + merged.query("SELECT count(*) FROM sweep_jobs") + \
        merged.query("SELECT count(*) FROM artifacts") + merged.query("SELECT count(*) FROM result_conflicts") + \
        merged.query("SELECT count(*) FROM job_events")


code, out, err = run_import(file_a)
check(code == 0, "import of part a: %s %s" % (out, err))
code, out, err = run_import(file_b)
check(code == 0, "import of part b: %s %s" % (out, err))
outcome_b = json.loads(out.strip().splitlines()[-1])  # the outcome is the last line
check(outcome_b["identical"] == 1 and outcome_b["added"] == 2,
      "part b: the shared point is recognised, two are new: %s" % outcome_b)

before = dump()
code, out, err = run_import(file_b)
check(code == 0 and not json.loads(out.strip().splitlines()[-1])["changed"], "a second import changes nothing: %s" % out)
check(dump() == before, "the database is as it was: %s -> %s" % (before, dump()))

with open(file_a, "rb") as f:
    whole = f.read()
cut = os.path.join(merged.dir, "cut.export.json")
with open(cut, "wb") as f:
    f.write(whole[: len(whole) * 2 // 3])
code, out, err = run_import(cut)
log = out + err  # spdlog writes to stdout
check(code == 1 and "file" in log and "nothing imported" in log, "a truncated file is refused: %s" % log)
check(dump() == before, "the truncated file imported nothing")

merged.start_server()
points = merged.get("/api/v1/phase-map?phi=0.4")["points"]
got = {(p["S"], p["R"]): p["class"] for p in points}
want = dict(labels_a)
want.update(labels_b)
check(len(points) == 4 and got == want, "the merged map is the union: %s against %s" % (got, want))
sweeps = merged.get("/api/v1/sweeps")["sweeps"]
check(len(sweeps) == 2 and all(s["imported"] and len(s["imported"]["database"]) == 32 for s in sweeps),
      "both sweeps are marked imported: %s" % [s["imported"] for s in sweeps])
check(sweeps[0]["imported"]["database"] != sweeps[1]["imported"]["database"], "from two databases")
for p in points:
    job = merged.get("/api/v1/jobs/%d" % p["job_id"])
    check(job["state"] == "succeeded" and job["result"]["origin"], "job %d imported" % p["job_id"])
    names = {a["name"] for a in merged.get("/api/v1/jobs/%d/artifacts" % p["job_id"])["artifacts"]}
    check({"frames.csv", "spacetime.npy", "summary.json"} <= names or {"frames.csv", "spacetime.npy"} <= names,
          "the run page's files: %s" % names)
    check(not any(n.startswith("snapshot_") and n.endswith(".npy") for n in names), "no particle snapshots")
    status, npy = merged.get_bytes("/api/v1/jobs/%d/artifacts/spacetime.npy" % p["job_id"])
    check(status == 200 and npy[:6] == b"\x93NUMPY", "the space-time map reads")
print("merged map: %d points from 2 parts, sizes %d and %d bytes" % (len(points), os.path.getsize(file_a),
                                                                      os.path.getsize(file_b)))
