"""Bad input to the real server with tokens: malformed JSON, wrong types, out-of-range S/R/phi,
oversized sweeps, unknown ids, missing or wrong tokens, a stale lease token. Each answer has its
status code and a JSON error naming the field, and the database file does not change.
Also: invalid command-line flags of both programs exit 2 naming the flag."""
import os
import subprocess
import time

from e2e_lib import Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "bad-input")
S, W = "submit-token", "worker-token"
env.start_server("--submit-token", S, "--worker-token", W, "--lease-seconds", "1",
                 "--rescue-interval", "0.2", "--max-sweep-points", "20")
ok_body = {"name": "ok", "points": [{"S": 0.05, "R": 1e-3, "phi": 0.4}],
           "numerics": {"cells_per_unit": 6, "eps_end": 0.03}}
env.submit(ok_body, S)
env.submit(dict(ok_body, name="second", points=[{"S": 0.06, "R": 1e-3, "phi": 0.4}]), S)
engine = env.get("/api/v1/health")["engine_version"]

# A lease that expires: its token goes stale.
status, lease = env.request("POST", "/api/v1/leases", {"worker": "w", "engine_version": engine}, W)
check(status == 200, "lease")
job = "/api/v1/jobs/%d" % lease["job_id"]
env.wait_for(lambda: env.get(job)["state"] == "queued", 10, "the lease to expire")
stale = lease["lease_token"]

def snapshot():
    tables = ["sweeps", "jobs", "sweep_jobs", "results", "artifacts", "job_events"]
    return [env.query("SELECT * FROM %s ORDER BY rowid" % t) for t in tables]

before = snapshot()
cases = [
    ("malformed JSON", "POST", "/api/v1/sweeps", b'{"name": "x", ', S, 400, "body"),
    ("NaN", "POST", "/api/v1/sweeps", b'{"name": "x", "points": [{"S": NaN, "R": 0.001, "phi": 0.4}]}', S, 400, "body"),
    ("wrong type", "POST", "/api/v1/sweeps", {"name": "x", "points": [{"S": "fast", "R": 1e-3, "phi": 0.4}]}, S, 422, "points[0].S"),
    ("S out of range", "POST", "/api/v1/sweeps", {"name": "x", "points": [{"S": 3, "R": 1e-3, "phi": 0.4}]}, S, 422, "points[0].S"),
    ("R out of range", "POST", "/api/v1/sweeps", {"name": "x", "points": [{"S": 0.1, "R": -1, "phi": 0.4}]}, S, 422, "points[0].R"),
    ("phi out of range", "POST", "/api/v1/sweeps", {"name": "x", "S": 0.1, "R": 1e-3, "phi": [0.1]}, S, 422, "phi"),
    ("oversized sweep", "POST", "/api/v1/sweeps", {"name": "x", "S": {"min": 0.01, "max": 0.1, "n": 5}, "R": {"min": 1e-3, "max": 1e-2, "n": 5}, "phi": 0.4}, S, 413, "S"),
    ("bad numerics", "POST", "/api/v1/sweeps", dict(ok_body, numerics={"cells_per_unit": "many"}), S, 422, "numerics.cells_per_unit"),
    ("missing token", "POST", "/api/v1/sweeps", ok_body, None, 401, "Authorization"),
    ("wrong token", "POST", "/api/v1/sweeps", ok_body, "guess", 403, "Authorization"),
    ("worker token for submitting", "POST", "/api/v1/sweeps", ok_body, W, 403, "Authorization"),
    ("unknown sweep", "GET", "/api/v1/sweeps/4242", None, None, 404, "id"),
    ("unknown job", "GET", "/api/v1/jobs/4242", None, None, 404, "id"),
    ("cancel unknown sweep", "POST", "/api/v1/sweeps/4242/cancel", None, S, 404, "id"),
    ("lease without token", "POST", "/api/v1/leases", {"worker": "w", "engine_version": engine}, None, 401, "Authorization"),
    ("stale heartbeat", "POST", job + "/heartbeat", {"lease_token": stale, "eps": 0.01}, W, 409, "lease_token"),
    ("stale fail", "POST", job + "/fail", {"lease_token": stale, "reason": "x"}, W, 409, "lease_token"),
    ("stale release", "POST", job + "/release", {"lease_token": stale}, W, 409, "lease_token"),
    ("bad filter", "GET", "/api/v1/jobs?state=finished", None, None, 422, "state"),
    ("priority beyond 64 bits", "POST", "/api/v1/sweeps",
     b'{"name": "x", "priority": 9223372036854775808, "points": [{"S": 0.05, "R": 0.001, "phi": 0.4}]}',
     S, 422, "priority"),
    ("NUL in the path", "GET", "/index.html%00.png", None, None, 400, "request"),
]
for what, method, path, body, token, code, field in cases:
    raw = body if isinstance(body, bytes) else None
    status, answer = env.request(method, path, None if raw else body, token, raw=raw)
    check(status == code, "%s: expected %d, got %d %s" % (what, code, status, answer))
    check(isinstance(answer, dict) and answer["error"]["field"] == field and answer["error"]["message"],
          "%s: error names %s: %s" % (what, field, answer))
check(snapshot() == before, "the bad requests changed nothing in the database")
status, answer = env.request("POST", "/api/v1/sweeps", None, S, raw=cases[-2][3])
check("9223372036854775808" in answer["error"]["message"],
      "the priority's message quotes the number sent: %s" % answer)

# The checkpoint form's numbers are decimal, whole and in range ("0.5" is, " 0.5" is not).
for eps in [" 0.5", "0x1p-3", "1e-400", "nan", "0.5 ", "2"]:
    boundary = "CkPt"
    form = "".join('--%s\r\nContent-Disposition: form-data; name="%s"\r\n\r\n%s\r\n' % (boundary, n, v)
                   for n, v in [("lease_token", stale), ("step", "10"), ("eps", eps),
                                ("checkpoint", "bytes")]) + "--%s--\r\n" % boundary
    status, answer = env.request_multipart("POST", job + "/checkpoint", form.encode(), boundary, W)
    check(status == 422 and answer["error"]["field"] == "eps",
          "checkpoint eps %r: expected 422 naming eps, got %d %s" % (eps, status, answer))
check(snapshot() == before, "the refused checkpoints changed nothing")

# The stale token cannot complete either (a raw multipart body; the worker's own uploads are
# covered by the other end-to-end tests).
boundary = "XyZ"
parts = "".join('--%s\r\nContent-Disposition: form-data; name="%s"\r\n\r\n%s\r\n' % (boundary, n, v)
                for n, v in [("lease_token", stale), ("summary", "{}")]) + "--%s--\r\n" % boundary
import urllib.request, urllib.error  # noqa: E402
req = urllib.request.Request(env.url + job + "/complete", data=parts.encode(), method="POST")
req.add_header("Content-Type", "multipart/form-data; boundary=" + boundary)
req.add_header("Authorization", "Bearer " + W)
try:
    urllib.request.urlopen(req, timeout=10)
    check(False, "a stale completion was accepted")
except urllib.error.HTTPError as e:
    check(e.code == 409, "stale completion refused with 409, got %d" % e.code)
check(snapshot() == before, "the stale completion changed nothing")
check(stop(env.server) == 0, "server exits 0")

# Command-line validation of both programs.
def run(args):
    p = subprocess.run(args, capture_output=True, text=True, timeout=20)
    return p.returncode, p.stdout + p.stderr

server = os.path.join(env.bin, "compaction-server")
worker = os.path.join(env.bin, "compaction-worker")
tokens = os.path.join(env.dir, "tokens")
with open(tokens, "w") as f:
    f.write("# role name token\nsubmit ana a-long-secret\nadmin bob another-secret\n")
for args, flag in [([server, "--port", "70000"], "--port"),
                   ([server, "--tokens", tokens], "--tokens"),
                   ([server, "--tokens", os.path.join(env.dir, "missing")], "--tokens"),
                   ([server, "--lease-seconds", "nan"], "--lease-seconds"),
                   ([server, "--host", "0.0.0.0"], "--host"),
                   ([server, "--bogus"], "--bogus"),
                   ([worker, "--threads", "0"], "--threads"),
                   ([worker, "--server", "ftp://x"], "--server"),
                   ([worker, "--runner", "/nonexistent"], "--runner")]:
    code, err = run(args)
    check(code == 2 and flag in err, "%s: exit %d, %s" % (" ".join(args[1:]), code, err.strip()))
code, out = run([server, "--help"])
check(code == 0, "--help exits 0")

# A worker with a wrong token stops at once (exit 2) instead of retrying forever.
env.start_server("--submit-token", S, "--worker-token", W)
code, err = run([worker, "--server", env.url, "--token", "wrong", "--idle-exit", "5"])
check(code == 2 and "403" in err, "wrong worker token: exit %d %s" % (code, err[-300:]))
check(stop(env.server) == 0, "server exits 0")
print("ok")
