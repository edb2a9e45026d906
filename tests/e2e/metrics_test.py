#!/usr/bin/env python3
"""/metrics of a real server after a few jobs: `promtool check metrics` finds nothing to say, and
the operator's series hold what happened. Fake workers over HTTP (lease, heartbeat, complete
with a minimal bundle) make the history exact:
  - w-fast completes a job at once, w-slow heartbeats and completes another after 1.2 s: the
    job-duration histogram counts 2, its sum is at least 1.2 s, the 1 s bucket holds at most one;
  - w-ghost leases the third job and goes silent: the rescuer requeues it (lease 1 s) and the
    expiry is counted under w-ghost, under nobody else;
  - workers last seen: every worker that called, at a time within the test's, a name with a
    quote and a backslash escaped;
  - build_info carries the engine version and source revision /health reports;
  - 520 more worker names: the last-seen series stay at 500 (the oldest names go).
promtool comes from Debian's prometheus package (scripts/install-promtool.sh); without it the
test is skipped (exit 77) unless COMPACTION_REQUIRE_PROMTOOL=1."""
import json
import os
import re
import shutil
import subprocess
import sys
import time
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_lib import Env, TINY, bin_dir_from_args, check, fail  # noqa: E402

promtool = shutil.which("promtool")
if not promtool:
    if os.environ.get("COMPACTION_REQUIRE_PROMTOOL") == "1":
        fail("promtool not found (scripts/install-promtool.sh installs it)")
    print("SKIP: promtool not found (scripts/install-promtool.sh installs it)")
    sys.exit(77)

env = Env(bin_dir_from_args(), "metrics")
env.start_server("--lease-seconds", "1", "--rescue-interval", "0.2")
health = env.get("/api/v1/health")
engine = health["engine_version"]
t_start = time.time()
sweep = env.submit({"name": "metrics", "points": [{"S": 0.05, "R": r, "phi": 0.4}
                                                  for r in (1e-3, 2e-3, 3e-3)], "numerics": TINY})


def lease(worker):
    status, l = env.request("POST", "/api/v1/leases", {"worker": worker, "engine_version": engine})
    check(status in (200, 204), "lease by %s -> %d %s" % (worker, status, l))
    return l if status == 200 else None


def complete(l):
    summary = {"status": "ok", "params": l["scene"], "engine_version": engine,
               "source_revision": "metrics-test", "eps_reached": l["scene"]["eps_end"],
               "wall_seconds": 0.01}
    b = b"metricsboundary"
    body = b"".join(
        b"--" + b + b'\r\nContent-Disposition: form-data; name="' + name + b'"' + extra + b"\r\n\r\n"
        + content + b"\r\n"
        for name, extra, content in [
            (b"lease_token", b"", l["lease_token"].encode()),
            (b"summary", b'; filename="summary.json"', json.dumps(summary).encode()),
            (b"files", b'; filename="frames.csv"', b"eps,stress\n0,0\n")]) + b"--" + b + b"--\r\n"
    req = urllib.request.Request("%s/api/v1/jobs/%d/complete" % (env.url, l["job_id"]), data=body,
                                 method="POST")
    req.add_header("Content-Type", "multipart/form-data; boundary=metricsboundary")
    with urllib.request.urlopen(req, timeout=30) as r:
        check(r.status == 200, "complete -> %d" % r.status)


complete(lease("w-fast"))
slow = lease("w-slow")
time.sleep(0.6)
status, _ = env.request("POST", "/api/v1/jobs/%d/heartbeat" % slow["job_id"],
                        {"lease_token": slow["lease_token"], "eps": 0.01})
check(status == 200, "heartbeat -> %d" % status)
time.sleep(0.6)
complete(slow)
ghost = lease("w-ghost")
env.wait_for(lambda: env.get("/api/v1/jobs/%d" % ghost["job_id"])["state"] == "queued", 30,
             "the rescuer to requeue w-ghost's job")
odd = 'node "7" \\ x'
complete(lease(odd))  # takes the requeued job
t_end = time.time()


def scrape():
    with urllib.request.urlopen(env.url + "/metrics", timeout=30) as r:
        check(r.headers.get("Content-Type", "").startswith("text/plain; version=0.0.4"),
              "the text format's content type")
        return r.read().decode()


def promtool_check(text):
    p = subprocess.run([promtool, "check", "metrics"], input=text, capture_output=True, text=True)
    check(p.returncode == 0 and not p.stdout.strip() and not p.stderr.strip(),
          "promtool check metrics -> %d:\n%s%s" % (p.returncode, p.stdout, p.stderr))


def series(text, name):
    """{labels text: value} of every sample of a metric name."""
    out = {}
    for line in text.splitlines():
        m = re.match(r"^%s(\{.*\})? (\S+)$" % re.escape(name), line)
        if m:
            out[m.group(1) or ""] = float(m.group(2))
    return out


text = scrape()
promtool_check(text)

build = series(text, "compaction_build_info")
check(build == {'{version="%s",revision="%s"}' % (engine, health["source_revision"]): 1.0},
      "build_info: %s" % build)

buckets = series(text, "compaction_job_duration_seconds_bucket")
count = series(text, "compaction_job_duration_seconds_count")[""]
total = series(text, "compaction_job_duration_seconds_sum")[""]
check(count == 3 and buckets['{le="+Inf"}'] == 3, "three jobs succeeded: %s" % buckets)
check(total >= 1.2, "the slow job took 1.2 s or more: sum %s" % total)
check(buckets['{le="1"}'] <= 2, "the slow job is not in the 1 s bucket: %s" % buckets)
values = list(buckets.values())
check(values == sorted(values), "buckets are cumulative: %s" % buckets)

expiries = series(text, "compaction_worker_lease_expiries_total")
check(expiries == {'{worker="w-ghost"}': 1.0}, "one expiry, w-ghost's: %s" % expiries)
check(series(text, "compaction_lease_expiries_total") == {"": 1.0}, "one expiry in all")

seen = series(text, "compaction_worker_last_seen_timestamp_seconds")
odd_label = '{worker="node \\"7\\" \\\\ x"}'
want = {'{worker="w-fast"}', '{worker="w-slow"}', '{worker="w-ghost"}', odd_label}
check(set(seen) == want, "workers seen: %s" % sorted(seen))
for w, at in seen.items():
    check(t_start - 1 <= at <= t_end + 1, "%s last seen at %s, outside the test's %s..%s"
          % (w, at, t_start, t_end))
check(seen['{worker="w-slow"}'] > seen['{worker="w-fast"}'], "the heartbeat counts as seen")

for i in range(520):
    lease("many-%03d" % i)  # the queue is empty: 204, but the worker was seen
text = scrape()
promtool_check(text)
seen = series(text, "compaction_worker_last_seen_timestamp_seconds")
check(len(seen) == 500, "at most 500 workers listed, got %d" % len(seen))
check('{worker="many-519"}' in seen and '{worker="w-fast"}' not in seen,
      "the newest names stay, the oldest go")
print("OK: metrics")
