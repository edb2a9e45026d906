"""Bodies cost the server what they weigh, not more:
- far beyond an endpoint's limit they cost nothing: four parallel 50 MB sweep requests with the
  right token, four without a token and four to the worker endpoints are refused from their
  headers (413, 401) and never read, and the server's peak resident memory (VmHWM) stays below
  200 MB; then a sweep still goes through;
- four parallel 50 MB imports, two valid (the committed exports of the Fig. 2 map and of
  example (c), each run carrying a movie) and two not (50 MB of empty runs; a 50 MB sweep
  request), keep the peak below 300 MB: the bodies are spooled to disk and read one run at a
  time, one import at a time. The valid ones merge every run; the others are refused naming
  their field and leave no file behind."""
import base64
import glob
import json
import os
import socket
import struct
import threading

from e2e_lib import Env, bin_dir_from_args, check

MB = 1 << 20
env = Env(bin_dir_from_args(), "memory")
S, W = "submit-secret", "worker-secret"
env.start_server("--submit-token", S, "--worker-token", W)


def peak_rss_mb():
    with open("/proc/%d/status" % env.server.pid) as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def post_big(path, token, results, i):
    head = ("POST %s HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
            "Content-Length: %d\r\n%sConnection: close\r\n\r\n"
            % (path, env.port, 50 * MB, "Authorization: Bearer %s\r\n" % token if token else ""))
    s = socket.create_connection(("127.0.0.1", env.port), timeout=30)
    answer = b""
    try:
        s.sendall(head.encode())
        chunk = b'{"name": "' + b"x" * (MB - 10)
        try:
            for _ in range(50):
                s.sendall(chunk)
        except (BrokenPipeError, ConnectionResetError):
            pass  # the server answered and stopped reading
        try:
            while True:
                data = s.recv(65536)
                if not data:
                    break
                answer += data
        except ConnectionResetError:
            pass
    finally:
        s.close()
    results[i] = answer


before = peak_rss_mb()
jobs = [("/api/v1/sweeps", S)] * 4 + [("/api/v1/sweeps", None)] * 4 + [("/api/v1/leases", W)] * 4
results = [None] * len(jobs)
threads = [threading.Thread(target=post_big, args=(p, t, results, i)) for i, (p, t) in enumerate(jobs)]
for t in threads:
    t.start()
for t in threads:
    t.join()
peak = peak_rss_mb()
for (path, token), answer in zip(jobs, results):
    want = b"413" if token else b"401"
    check(answer and answer.split(b" ", 2)[1] == want,
          "POST %s (token %s) of 50 MB: expected %s, got %r" % (path, bool(token), want, answer[:200]))
check(peak < 200, "peak RSS %.0f MB (%.0f MB before the bodies)" % (peak, before))
env.submit({"name": "after", "points": [{"S": 0.05, "R": 1e-3, "phi": 0.4}]}, S)
print("12 parallel 50 MB bodies refused; server peak RSS %.1f MB (%.1f MB before)" % (peak, before))

# --- imports ---
STUDIES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "studies")


def movie(n_particles, n_frames):
    """movie.bin (schema/movie-format.md) with zeroed frames."""
    frame = (8 + 5 * n_particles + 7) // 8 * 8
    head = b"CSMOVIE1" + struct.pack("<IIQQQd4ddI", 1, 96, n_particles, n_frames, frame, 0.02,
                                     0.0, 0.5, 0.0, 1.0, 4.0, 0)
    return head.ljust(96, b"\0") + bytes(frame * n_frames)


def padded_export(name, target):
    """A committed export with a movie added to each run, about `target` bytes in all."""
    path = glob.glob(os.path.join(STUDIES, "**", name), recursive=True)[0]
    with open(path) as f:
        doc = json.load(f)
    runs = len(doc["runs"])
    per_run = target * 3 // 4 // runs
    data = movie((per_run - 104) // 5, 1)
    encoded = base64.b64encode(data).decode()
    for run in doc["runs"]:
        run["artifacts"] = [a for a in run["artifacts"] if a["name"] != "movie.bin"] + [
            {"name": "movie.bin", "content_type": "application/octet-stream", "size": len(data),
             "data": encoded}]
    return json.dumps(doc).encode(), runs


valid_map, map_runs = padded_export("sweep-2.export.json", 50 * MB)
valid_c, c_runs = padded_export("example-c.export.json", 50 * MB)
empty_runs = b"{\"runs\": [" + b",".join([b"{}"] * (50 * MB // 3)) + b"]}"
with open(glob.glob(os.path.join(STUDIES, "**", "example-c-reference.export.json"), recursive=True)[0]) as f:
    big_request = json.load(f)
big_request["sweep"]["request"]["padding"] = "x" * (50 * MB)
big_request = json.dumps(big_request).encode()
for body in (valid_map, valid_c, empty_runs, big_request):
    check(45 * MB < len(body) < 70 * MB, "an import body of %.0f MB" % (len(body) / MB))


def post_import(body, results, i):
    head = ("POST /api/v1/imports HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: application/json\r\n"
            "Content-Length: %d\r\nAuthorization: Bearer %s\r\nConnection: close\r\n\r\n"
            % (env.port, len(body), S))
    answer = b""
    try:
        s = socket.create_connection(("127.0.0.1", env.port), timeout=300)
        try:
            s.sendall(head.encode() + body)
            while True:
                data = s.recv(65536)
                if not data:
                    break
                answer += data
        finally:
            s.close()
        status = int(answer.split(b" ", 2)[1])
        results[i] = (status, json.loads(answer.partition(b"\r\n\r\n")[2]))
    except Exception as e:  # reported by the checks below, with what came back
        results[i] = (0, {"exception": repr(e), "answer": answer[:300].decode(errors="replace")})


folder = env.db + ".artifacts"
before_folders = set(os.listdir(folder))
before = peak_rss_mb()
bodies = [valid_map, valid_c, empty_runs, big_request]
results = [None] * len(bodies)
threads = [threading.Thread(target=post_import, args=(b, results, i)) for i, b in enumerate(bodies)]
for t in threads:
    t.start()
for t in threads:
    t.join()
peak = peak_rss_mb()
# The two maps share a few points: whichever merged second found those runs here already.
for (status, outcome), runs, what in [(results[0], map_runs, "the map"), (results[1], c_runs, "example (c)")]:
    check(status == 200 and outcome.get("added", 0) + outcome.get("identical", 0) == runs
          and outcome["identical"] < 10,
          "%s's export: %s" % (what, outcome))
added_runs = results[0][1]["added"] + results[1][1]["added"]
check(results[2][0] == 422 and results[2][1].get("error", {}).get("field") == "format",
      "empty runs: %s" % (results[2],))
check(results[3][0] == 422 and results[3][1].get("error", {}).get("field") == "sweep.request.padding",
      "a 50 MB request: %s" % (results[3],))
check(peak < 300, "four parallel 50 MB imports: peak RSS %.0f MB (%.0f MB before)" % (peak, before))
added = set(os.listdir(folder)) - before_folders
check(len(added) == added_runs, "one artifact folder per run added, nothing else: %d for %d runs"
      % (len(added), added_runs))
listing = env.get("/api/v1/sweeps")
check(len(json.dumps(listing)) < 4 * MB, "the sweeps list stays small: %d bytes" % len(json.dumps(listing)))
print("4 parallel 50 MB imports (%d runs added, 2 files refused); server peak RSS %.1f MB (%.1f MB before)"
      % (added_runs, peak, before))
