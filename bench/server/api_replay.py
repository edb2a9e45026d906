"""Two builds of compaction-server give the same answers: a recorded set of requests
(bench/server/api_requests.txt) replayed against each build, on copies of one database, and
their answers (status, content type, body) compared byte for byte. A refactoring that must not
change the API (issue 48: "the API's answers identical on a recorded set of requests") proves it
with this.

The database: the committed exports (studies/phase_map/results/*.export.json) imported with
the baseline's --import, then a small grid and an adaptive sweep submitted (queued jobs,
planned points) through the baseline. Each build then serves a copy of that file. Answers
that hold the time of the request are left out of the request set (health, metrics, the
archive export with its exported_at);
every other byte must agree.

usage: python3 bench/server/api_replay.py --bin build/bin --baseline OLD/build/bin
         [--requests bench/server/api_requests.txt] [--out bench/results/api_replay.md]
"""
import argparse
import glob
import http.client
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def start(binary_dir, db, log):
    port_file = db + ".port"
    if os.path.exists(port_file):
        os.remove(port_file)
    proc = subprocess.Popen([os.path.join(binary_dir, "compaction-server"), "--db", db, "--port", "0",
                             "--port-file", port_file, "--log-level", "warn"],
                            stdout=log, stderr=subprocess.STDOUT)
    deadline = time.time() + 30
    while not os.path.exists(port_file):
        if proc.poll() is not None or time.time() > deadline:
            sys.exit("the server in %s did not start" % binary_dir)
        time.sleep(0.05)
    with open(port_file) as f:
        return proc, int(f.read())


def stop(proc):
    proc.terminate()
    proc.wait(timeout=30)


def request(port, method, path, body=None):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    headers = {"Content-Type": "application/json"} if body is not None else {}
    c.request(method, path, body=body, headers=headers)
    r = c.getresponse()
    data = r.read()
    c.close()
    return r.status, r.getheader("Content-Type"), data


def make_database(baseline, db, log):
    for export in sorted(glob.glob(os.path.join(ROOT, "studies", "**", "*.export.json"), recursive=True)):
        subprocess.run([os.path.join(baseline, "compaction-server"), "--db", db, "--import", export],
                       stdout=log, stderr=subprocess.STDOUT, check=True)
    proc, port = start(baseline, db, log)
    try:
        grid = {"name": "replay grid", "phi": 0.4, "S": {"min": 3e-3, "max": 3e-2, "n": 3, "scale": "log"},
                "R": {"min": 1e-5, "max": 1e-2, "n": 4, "scale": "log"}, "numerics": {"preset": "fast"}}
        adaptive = {"name": "replay adaptive", "phi": 0.5,
                    "adaptive": {"S": {"min": 3e-3, "max": 3e-2}, "R": {"min": 1e-5, "max": 1e-2},
                                 "initial": {"S": 3, "R": 3}, "resolution_decades": 0.25, "budget": 20}}
        for body in (grid, adaptive):
            status, _, answer = request(port, "POST", "/api/v1/sweeps", json.dumps(body))
            if status != 201:
                sys.exit("could not submit %s: %d %s" % (body["name"], status, answer[:300]))
    finally:
        stop(proc)


def replay(binary_dir, db, requests, log):
    proc, port = start(binary_dir, db, log)
    try:
        return [request(port, m, p, b) for m, p, b in requests]
    finally:
        stop(proc)


def read_requests(path):
    out = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            method, rest = line.split(" ", 1)
            path, _, body = rest.partition(" ")
            out.append((method, path, body or None))
    return out


def strip_added(old, new, added):
    """new without the keys in added that old does not have, recursively along the shared
    structure; anything else is kept so that it still compares."""
    if isinstance(new, dict) and isinstance(old, dict):
        return {k: strip_added(old[k], v, added) if k in old else v
                for k, v in new.items() if k in old or k not in added}
    if isinstance(new, list) and isinstance(old, list) and len(new) == len(old):
        return [strip_added(o, n, added) for o, n in zip(old, new)]
    return new


def without_added(old_body, new_body, added):
    """The build's JSON body re-serialised without the added keys, in the baseline's own form
    when nothing else differs (so the byte comparison stays byte for byte)."""
    try:
        old, new = json.loads(old_body), json.loads(new_body)
    except ValueError:
        return new_body
    stripped = strip_added(old, new, added)
    return old_body if stripped == old else new_body


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", required=True, help="the build to check (its bin/)")
    ap.add_argument("--baseline", required=True, help="the build it must agree with (its bin/)")
    ap.add_argument("--requests", default=os.path.join(ROOT, "bench", "server", "api_requests.txt"))
    ap.add_argument("--out", help="a Markdown report to write")
    ap.add_argument("--added", action="append", default=[], metavar="KEY",
                    help="a JSON key the build adds on purpose: removed, at any depth, from the "
                         "build's JSON answers where the baseline's answer has no such key, "
                         "before comparing (repeatable)")
    ap.add_argument("--changed", action="append", default=[], metavar="PATH",
                    help="a request path whose answer changes on purpose (such as the "
                         "OpenAPI document that describes an added key); listed, not compared")
    a = ap.parse_args()
    requests = read_requests(a.requests)
    work = tempfile.mkdtemp(prefix="api-replay-")
    try:
        with open(os.path.join(work, "server.log"), "w") as log:
            db = os.path.join(work, "base.db")
            make_database(a.baseline, db, log)
            answers = {}
            for name, binary in (("baseline", a.baseline), ("build", a.bin)):
                copy = os.path.join(work, name + ".db")
                shutil.copyfile(db, copy)
                if os.path.isdir(db + ".artifacts"):
                    shutil.copytree(db + ".artifacts", copy + ".artifacts")
                answers[name] = replay(binary, copy, requests, log)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    differ = []
    for (m, p, _), old, new in zip(requests, answers["baseline"], answers["build"]):
        if p in a.changed:
            continue
        if a.added and old[:2] == new[:2] and old[1] == "application/json":
            new = new[:2] + (without_added(old[2], new[2], set(a.added)),)
        if old != new:
            differ.append((m, p, old[:2] + (old[2][:200],), new[:2] + (new[2][:200],)))
    total_bytes = sum(len(x[2]) for x in answers["build"])
    lines = ["# API answers of two builds", "",
             "Made by `python3 bench/server/api_replay.py --bin %s --baseline %s%s`." % (
                 a.bin, a.baseline,
                 "".join(" --added %s" % k for k in a.added) + "".join(" --changed %s" % c for c in a.changed)), "",
             "%d requests (`%s`), %d bytes of answers: %s." % (
                 len(requests), os.path.relpath(a.requests, ROOT), total_bytes,
                 "every answer identical (status, content type, body)" if not differ
                 else "%d answers differ" % len(differ))]
    if a.added:
        lines += ["", "Keys the build adds on purpose, removed from its answers before comparing "
                  "(where the baseline has none): %s." % ", ".join("`%s`" % k for k in a.added)]
    if a.changed:
        lines += ["", "Answers changed on purpose, not compared: %s." % ", ".join("`%s`" % c for c in a.changed)]
    for m, p, old, new in differ:
        lines += ["", "- `%s %s`: baseline %r, build %r" % (m, p, old, new)]
    report = "\n".join(lines) + "\n"
    print(report)
    if a.out:
        with open(a.out, "w") as f:
            f.write(report)
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
