"""Checkpoints end to end: a worker SIGTERMed mid-run uploads the checkpoint its runner writes
on the signal and releases the lease; a second worker leases the job with that checkpoint,
resumes from it and uploads a result whose every file equals, bit for bit, the bundle of an
uninterrupted compaction-run of the same scene (summary.json but for its wall times); the job's
detail and events show the checkpoint and the resume (step, eps, worker); the checkpoint is
gone once the job succeeded. Also: the checkpoint endpoints' refusals (token, lease, fields)."""
import json
import os
import signal
import subprocess
import time

from e2e_lib import STOPPABLE, STOPPABLE_POINT, Env, bin_dir_from_args, check, stop

# Wall times and what the run says of its own speed: the only outputs that may differ.
TIMING_KEYS = {"wall_seconds", "ns_per_particle_step", "stage_seconds"}


def without_timings(summary):
    return {k: (without_timings(v) if isinstance(v, dict) else v)
            for k, v in summary.items() if k not in TIMING_KEYS}


env = Env(bin_dir_from_args(), "checkpoint-resume")
env.start_server("--lease-seconds", "300")  # a long lease: only the release requeues in time
# A run long enough to be stopped in the middle, seen past eps 0.01 at about 0.2-0.4 of its
# course; a snapshot on each side of the stop.
numerics = dict(STOPPABLE, snapshot_eps=[0.004, 0.045])
sweep = env.submit({"name": "ckpt", "points": [STOPPABLE_POINT], "numerics": numerics})
job_id = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"][0]["id"]

first = env.start_worker("first")
env.wait_for(lambda: (env.get("/api/v1/jobs/%d" % job_id).get("progress_eps") or 0) > 0.01,
             120, "the first worker's run to pass eps 0.01")
check(stop(first, signal.SIGTERM, timeout=20) == 0, "the first worker exits 0 on SIGTERM")

job = env.get("/api/v1/jobs/%d" % job_id)
check(job["state"] == "queued", "queued again at once, got %s" % job["state"])
kinds = [e["kind"] for e in job["events"]]
check(kinds[-2:] == ["checkpoint", "released"],
      "the checkpoint is uploaded, then the lease released: %s" % kinds)
ckpt = job["checkpoint"]
check(ckpt is not None and ckpt["worker"] == "first" and ckpt["step"] > 0 and
      0.01 < ckpt["eps"] < 0.05, "the job holds the first worker's checkpoint: %s" % ckpt)
check(ckpt["url"] == "/api/v1/jobs/%d/checkpoint" % job_id, "its url: %s" % ckpt["url"])
status, data = env.get_bytes(ckpt["url"])
check(status == 200 and len(data) == ckpt["size"] and data[:8] == b"CMPCKPT\n",
      "the checkpoint's bytes: %d bytes, magic %r" % (len(data), data[:8]))
check(job["resumes"] == [], "no resume yet")
check(len(os.listdir(env.db + ".checkpoints")) == 1, "one checkpoint folder on disk")

# Uploads need the live lease (409), the fields (422) and a known job (404).
boundary = "b0undary"


def form(fields):
    parts = []
    for name, value in fields.items():
        parts.append(("--%s\r\nContent-Disposition: form-data; name=\"%s\"%s\r\n\r\n" %
                      (boundary, name, "; filename=\"c.bin\"" if name == "checkpoint" else "")).encode()
                     + value + b"\r\n")
    return b"".join(parts) + ("--%s--\r\n" % boundary).encode()


def upload(job, fields):
    import urllib.request
    import urllib.error
    req = urllib.request.Request(env.url + "/api/v1/jobs/%d/checkpoint" % job, data=form(fields),
                                 method="POST")
    req.add_header("Content-Type", "multipart/form-data; boundary=" + boundary)
    try:
        with urllib.request.urlopen(req, timeout=30) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


good = {"lease_token": b"0" * 32, "step": b"10", "eps": b"0.01", "checkpoint": b"xx"}
status, body = upload(job_id, good)
check(status == 409 and body["error"]["field"] == "lease_token", "stale lease: %d %s" % (status, body))
status, body = upload(job_id, dict(good, step=b"-1"))
check(status == 422 and body["error"]["field"] == "step", "negative step: %d %s" % (status, body))
status, body = upload(job_id, dict(good, eps=b"nan"))
check(status == 422 and body["error"]["field"] == "eps", "eps nan: %d %s" % (status, body))
status, body = upload(job_id, {k: v for k, v in good.items() if k != "checkpoint"})
check(status == 422 and body["error"]["field"] == "checkpoint", "no file: %d %s" % (status, body))
status, body = upload(job_id + 1000, good)
check(status == 404, "unknown job: %d %s" % (status, body))
check(env.get("/api/v1/jobs/%d" % job_id)["checkpoint"] == ckpt, "the refusals changed nothing")

second = env.start_worker("second")
env.wait_sweep_done(sweep["id"], 240)
check(stop(second) == 0, "the second worker exits 0")
job = env.get("/api/v1/jobs/%d" % job_id)
check(job["state"] == "succeeded" and job["result"]["worker"] == "second",
      "the second worker finished it: %s" % job["state"])
check(len(job["resumes"]) == 1, "one resume: %s" % job["resumes"])
resume = job["resumes"][0]
check(resume["worker"] == "second" and resume["step"] == ckpt["step"] and
      resume["eps"] == ckpt["eps"], "resumed by the second worker from the checkpoint: %s" % resume)
kinds = [e["kind"] for e in job["events"]]
check("resumed" in kinds and kinds.index("resumed") > kinds.index("released"),
      "a 'resumed' event after the release: %s" % kinds)
message = [e for e in job["events"] if e["kind"] == "resumed"][0]["message"]
check(("step %d" % ckpt["step"]) in message, "the event names the step: %s" % message)
check(job["checkpoint"] is None, "the checkpoint is removed once the job succeeded")
check(os.listdir(env.db + ".checkpoints") == [], "and its folder")

# The same scene run in one go, as the worker runs it (threads 1).
ref_dir = os.path.join(env.dir, "reference")
scene_file = os.path.join(env.dir, "scene.json")
with open(scene_file, "w") as f:
    json.dump(dict(job["scene"], threads=1), f)
t = time.time()
rc = subprocess.run([os.path.join(env.bin, "compaction-run"), "--scene", scene_file, "--out",
                     ref_dir, "--progress", "none"], capture_output=True, text=True)
check(rc.returncode == 0, "the uninterrupted run: %s" % rc.stderr[-2000:])
reference_seconds = time.time() - t

names = sorted(a["name"] for a in env.get("/api/v1/jobs/%d/artifacts" % job_id)["artifacts"])
check(names == sorted(os.listdir(ref_dir)), "the same files: %s against %s" %
      (names, sorted(os.listdir(ref_dir))))
check(any(n.startswith("snapshot_0.004") for n in names) and
      any(n.startswith("snapshot_0.04") for n in names), "both snapshots: %s" % names)
for name in names:
    status, data = env.get_bytes("/api/v1/jobs/%d/artifacts/%s" % (job_id, name))
    with open(os.path.join(ref_dir, name), "rb") as f:
        ref = f.read()
    if name == "summary.json":
        a, b = without_timings(json.loads(data)), without_timings(json.loads(ref))
        check(a == b, "summary.json differs from the uninterrupted run's: %s" %
              [k for k in set(a) | set(b) if a.get(k) != b.get(k)])
    else:
        check(data == ref, "%s differs from the uninterrupted run's" % name)
print("ok (checkpoint at step %d, eps %.4f, %d bytes; %d files equal; reference run %.1f s)" %
      (ckpt["step"], ckpt["eps"], ckpt["size"], len(names), reference_seconds))
