"""Malformed requests against the real server, as an attacker on loopback would send them:
invalid UTF-8 in paths, query strings, headers, JSON strings and multipart names; deep nesting;
huge numbers; oversized bodies; wrong content types; foreign origins and every mix of tokens;
imports of broken or forged export files; labels with bad classes, NUL and control characters;
checkpoint forms with bad numbers; duplicate singleton headers, a missing Host, obs-fold and
header lines without a colon.
Seeded and bounded (at least 5 000 requests, at most 6 000, within 240 s). After each request the
server must still answer /api/v1/health; each answer is a 4xx with a JSON error naming a field
(never a 500); the database's dump and the artifacts folder are the same at the end as at the
start; the log holds no raw control character (no forged lines)."""
import hashlib
import json
import os
import random
import socket
import sqlite3
import time

from e2e_lib import Env, bin_dir_from_args, check, fail

SEED = 20261201
MIN_REQUESTS, MAX_REQUESTS, TIME_BUDGET = 5000, 6000, 240.0

env = Env(bin_dir_from_args(), "fuzz")
S, W = "submit-secret", "worker-secret"
env.start_server("--submit-token", S, "--worker-token", W, "--lease-seconds", "3600",
                 "--max-sweep-points", "50", "--max-upload-mb", "16")
env.submit({"name": "target", "points": [{"S": 0.05, "R": 1e-3, "phi": 0.4}],
            "numerics": {"cells_per_unit": 6, "eps_end": 0.03}}, S)
engine = env.get("/api/v1/health")["engine_version"]
status, lease = env.request("POST", "/api/v1/leases", {"worker": "w", "engine_version": engine}, W)
check(status == 200, "a job to aim the worker endpoints at")
JOB = lease["job_id"]
LIVE = lease["lease_token"]  # used only in requests that are invalid for another reason
HOST = "127.0.0.1:%d" % env.port


def db_state():
    con = sqlite3.connect("file:%s?mode=ro" % env.db, uri=True, timeout=10)
    try:
        dump = "\n".join(con.iterdump())
    finally:
        con.close()
    folder = env.db + ".artifacts"
    files = sorted(os.listdir(folder)) if os.path.isdir(folder) else []
    return hashlib.sha256(dump.encode()).hexdigest(), files


def exchange(raw, timeout=10.0):
    """Sends raw bytes, reads the answer to the end (the request asks to close); returns
    (status, headers, body) or None when the server closed without an answer."""
    s = socket.create_connection(("127.0.0.1", env.port), timeout=timeout)
    try:
        try:
            s.sendall(raw)
        except (BrokenPipeError, ConnectionResetError):
            pass  # the server answered and closed before the whole body went out
        data = b""
        while True:
            try:
                chunk = s.recv(65536)
            except ConnectionResetError:
                break
            if not chunk:
                break
            data += chunk
    finally:
        s.close()
    if not data:
        return None
    head, _, body = data.partition(b"\r\n\r\n")
    lines = head.split(b"\r\n")
    parts = lines[0].split(b" ", 2)
    headers = {}
    for line in lines[1:]:
        k, _, v = line.partition(b":")
        headers[k.strip().lower().decode("latin-1")] = v.strip().decode("latin-1")
    return int(parts[1]), headers, body


def request(method, path, headers=(), body=b"", content_length=None):
    if isinstance(path, str):
        path = path.encode()
    if isinstance(body, str):
        body = body.encode()
    lines = [method.encode() + b" " + path + b" HTTP/1.1", b"Host: " + HOST.encode(),
             b"Connection: close"]
    for k, v in headers:
        lines.append((k.encode() if isinstance(k, str) else k) + b": " +
                     (v.encode() if isinstance(v, str) else v))
    if body or content_length is not None:
        lines.append(b"Content-Length: %d" % (len(body) if content_length is None else content_length))
    return b"\r\n".join(lines) + b"\r\n\r\n" + body


def health_ok():
    r = exchange(request("GET", "/api/v1/health"))
    return r is not None and r[0] == 200 and json.loads(r[2])["status"] == "ok"


rng = random.Random(SEED)


def junk_bytes(n):
    return bytes(rng.choice([0xff, 0xfe, 0xc3, 0x28, 0x80, 0xbf, 0xe2, 0x82, 0x00, 0x1b, 0x0a,
                             0x0d, 0x7f, 0x9b, 0x41, 0x22, 0x5c]) for _ in range(n))


def pct(b):
    return "".join("%%%02X" % c for c in b)


def deep(n):
    return "[" * n + "]" * n


def auth(kind):
    return [("Authorization", "Bearer " + kind)] if kind else []


JSON = [("Content-Type", "application/json")]
WRITES = ["/api/v1/sweeps", "/api/v1/sweeps/1/cancel", "/api/v1/leases",
          "/api/v1/jobs/%d/heartbeat" % JOB, "/api/v1/jobs/%d/fail" % JOB,
          "/api/v1/jobs/%d/release" % JOB]
TOKEN_OF = {"/api/v1/sweeps": S, "/api/v1/sweeps/1/cancel": S}
POINT = '{"S": 0.05, "R": 0.001, "phi": 0.4}'


def token_for(path):
    return TOKEN_OF.get(path, W)


def case_path_utf8():
    path = "/api/v1/" + rng.choice(["", "jobs/", "sweeps/", "x"]) + pct(junk_bytes(rng.randint(1, 8)))
    return "path", request(rng.choice(["GET", "POST"]), path, JSON if rng.random() < 0.5 else [],
                           b"{}" if rng.random() < 0.3 else b"")


def case_raw_path_bytes():
    path = b"/api/v1/" + junk_bytes(rng.randint(1, 6)).replace(b" ", b"").replace(b"\r", b"") \
        .replace(b"\n", b"")
    return "raw path", request("GET", path)


def case_query():
    ep, name = rng.choice([("/api/v1/jobs", "phi"), ("/api/v1/jobs", "limit"),
                           ("/api/v1/jobs", "state"), ("/api/v1/jobs", "sweep"),
                           ("/api/v1/phase-map", "phi"), ("/api/v1/sweeps", "offset"),
                           ("/api/v1/sweeps/1/export", "format")])
    # Values each parameter refuses (a negative number is a valid phi filter, matching nothing).
    value = rng.choice([pct(junk_bytes(rng.randint(1, 6))), "1e999", "nan", "%00", "0x10", "9" * 400]
                       + ([] if name == "phi" else ["-" + "9" * 40]))
    return "query", request("GET", "%s?%s=%s" % (ep, name, value))


def case_header_utf8():
    path = rng.choice(WRITES)
    which = rng.choice(["Authorization", "Content-Type", "Origin", "Host"])
    junk = junk_bytes(rng.randint(1, 6)).replace(b"\r", b"").replace(b"\n", b"")
    headers = [("Content-Type", "application/json")] + auth(token_for(path))
    if which == "Authorization":
        headers = [("Content-Type", "application/json"), ("Authorization", b"Bearer " + junk)]
    elif which == "Content-Type":
        headers = [("Content-Type", b"application/" + junk)] + auth(token_for(path))
    elif which == "Origin":
        headers.append(("Origin", b"http://" + junk))
    else:
        raw = request("POST", path, headers, b"{}")
        return "header", raw.replace(b"Host: " + HOST.encode(), b"Host: " + junk + b".example")
    return "header", request("POST", path, headers, b"{}")


def case_json_string_utf8():
    path = rng.choice(WRITES)
    junk = junk_bytes(rng.randint(1, 5)).replace(b'"', b"").replace(b"\\", b"")
    body = b'{"name": "' + junk + b'", "worker": "' + junk + b'", "lease_token": "' + junk + \
        b'", "reason": "' + junk + b'", "points": [' + POINT.encode() + b']}'
    return "json string", request("POST", path, JSON + auth(token_for(path)), body)


def case_deep_nesting():
    path, key = rng.choice([("/api/v1/sweeps", "name"), ("/api/v1/sweeps", "numerics"),
                            ("/api/v1/leases", "worker"),
                            ("/api/v1/jobs/%d/heartbeat" % JOB, "eps"),
                            ("/api/v1/jobs/%d/fail" % JOB, "reason")])
    n = rng.choice([65, 100, 1000, 70000])
    body = '{"%s": %s, "lease_token": "stale", "points": [%s]}' % (key, deep(n), POINT)
    return "deep", request("POST", path, JSON + auth(token_for(path)), body)


def case_huge_numbers():
    path = "/api/v1/sweeps"
    field = rng.choice(["S", "R", "phi", "priority", "max_attempts", "n"])
    value = rng.choice(["1e999", "-1e999", "1e308", "99999999999999999999999",
                        "1" + "0" * 400, "4e-400", "1.0e+", "0x1F"])
    if field == "n":
        body = '{"name": "x", "S": {"min": 0.01, "max": 0.1, "n": %s}, "R": 0.001, "phi": 0.4}' % value
    elif field in ("priority", "max_attempts"):
        body = '{"name": "x", "%s": %s, "points": [%s]}' % (field, value, POINT)
    else:
        point = json.loads(POINT)
        body = '{"name": "x", "points": [%s]}' % json.dumps(point).replace(
            '"%s": %s' % (field, json.dumps(point[field])), '"%s": %s' % (field, value))
    return "huge number", request("POST", path, JSON + auth(S), body)


def case_oversized():
    path = rng.choice(WRITES + ["/api/v1/jobs/%d/complete" % JOB, "/api/v1/health"])
    # Beyond each endpoint's limit (the upload's is --max-upload-mb 16 here).
    declared = rng.choice([50 << 20, 1 << 40, 10 ** 18] + ([] if path.endswith("complete") else [2 << 20]))
    method = "GET" if path.endswith("health") else "POST"
    ctype = [("Content-Type", "multipart/form-data; boundary=x")] if path.endswith("complete") else JSON
    return "oversized", request(method, path, ctype + auth(token_for(path)),
                                b"x" * rng.randint(0, 4096), content_length=declared)


def case_chunked():
    path = rng.choice(WRITES)
    raw = request("POST", path, JSON + auth(token_for(path)) + [("Transfer-Encoding", "chunked")])
    return "chunked", raw + b"5\r\nhello\r\n0\r\n\r\n"


def case_content_type():
    path = rng.choice(WRITES + ["/api/v1/jobs/%d/complete" % JOB])
    ctype = rng.choice(["text/plain", "application/x-www-form-urlencoded", "multipart/form-data",
                        "application/jsonx", "", "application/json" if path.endswith("complete") else "text/html"])
    headers = ([("Content-Type", ctype)] if ctype else []) + auth(token_for(path))
    return "content type", request("POST", path, headers, '{"name": "x", "points": [%s]}' % POINT)


def case_origin():
    path = rng.choice(WRITES)
    origin = rng.choice(["http://evil.example", "null", "http://127.0.0.1:1", "https://" + HOST + ".evil",
                         "file://", "http://localhost"])
    headers = JSON + auth(token_for(path)) + [("Origin", origin)]
    if rng.random() < 0.3:
        headers = JSON + auth(token_for(path)) + [("Sec-Fetch-Site", "cross-site")]
    return "origin", request("POST", path, headers, '{"name": "x", "points": [%s]}' % POINT)


def case_tokens():
    path = rng.choice(WRITES + ["/api/v1/jobs/%d/complete" % JOB])
    right = token_for(path)
    choice = rng.choice(["none", "wrong", "other", "empty", "basic", "long"])
    headers = {"none": [], "wrong": auth("guess"), "other": auth(W if right == S else S),
               "empty": [("Authorization", "Bearer ")], "basic": [("Authorization", "Basic eDp5")],
               "long": auth("x" * 5000)}[choice]
    ctype = [("Content-Type", "multipart/form-data; boundary=x")] if path.endswith("complete") else JSON
    return "token", request("POST", path, ctype + headers,
                            '{"name": "x", "worker": "w", "engine_version": "%s", "points": [%s]}'
                            % (engine, POINT))


def multipart(parts, boundary="fuzzboundary"):
    out = b""
    for name, filename, content in parts:
        disp = b'form-data; name="' + name + b'"'
        if filename is not None:
            disp += b'; filename="' + filename + b'"'
        out += b"--" + boundary.encode() + b"\r\nContent-Disposition: " + disp + b"\r\n\r\n" + \
            content + b"\r\n"
    return out + b"--" + boundary.encode() + b"--\r\n"


def case_multipart():
    kind = rng.choice(["bad filename", "bad field", "truncated", "no summary", "deep summary",
                       "stale token"])
    token = b"stale" if kind == "stale token" else LIVE.encode()
    summary = b'{"status": "ok"}'
    parts = [(b"lease_token", None, token), (b"summary", b"summary.json", summary)]
    if kind == "bad filename":
        parts.append((b"files", junk_bytes(3).replace(b'"', b"") + b".csv", b"eps\n"))
    elif kind == "bad field":
        parts.append((b"fi" + junk_bytes(2).replace(b'"', b""), b"a.csv", b"eps\n"))
    elif kind == "no summary":
        parts = parts[:1]
    elif kind == "deep summary":
        parts[1] = (b"summary", b"summary.json", ('{"status": %s}' % deep(5000)).encode())
    body = multipart(parts)
    if kind == "truncated":
        body = body[: rng.randint(10, len(body) - 10)]
    return "multipart " + kind, request("POST", "/api/v1/jobs/%d/complete" % JOB,
                                        [("Content-Type", "multipart/form-data; boundary=fuzzboundary")]
                                        + auth(W), body)


def case_malformed_line():
    close = b"Connection: close\r\n"
    raw = rng.choice([b"GARBAGE\r\n\r\n", b"GET\r\n\r\n", b"GET / HTTP/9.9\r\n" + close + b"\r\n",
                      b"GET /" + b"a" * 9000 + b" HTTP/1.1\r\nHost: x\r\n" + close + b"\r\n",
                      b"POST /api/v1/sweeps HTTP/1.1\r\nHost: " + HOST.encode() +
                      b"\r\nContent-Length: -5\r\n" + close + b"\r\n",
                      b"GET /api/v1/health HTTP/1.1\r\nHost: " + HOST.encode() +
                      b"\r\nRange: bytes=zz\r\n" + close + b"\r\n",
                      b"GET /api/v1/health HTTP/1.1\r\n" + close + b"X-Pad: " + b"y" * 70000 +
                      b"\r\n\r\n"])
    return "request line", raw


EXPORT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "studies", "phase_map",
                      "results", "example-c-reference.export.json")
with open(EXPORT) as f:
    GOOD_EXPORT = json.load(f)


def case_import():
    doc = json.loads(json.dumps(GOOD_EXPORT))
    run = rng.randrange(len(doc["runs"]))
    kind = rng.choice(["junk", "truncated", "class", "origin twice", "scene", "summary status",
                       "npy", "request", "empty runs", "label nul", "version"])
    if kind == "junk":
        body = junk_bytes(rng.randint(1, 200))
    elif kind == "truncated":
        text = json.dumps(doc).encode()
        body = text[: rng.randint(1, len(text) - 1)]
    else:
        if kind == "class":
            doc["runs"][run]["result"]["class"] = rng.choice(["z", 5, "a" * 300])
        elif kind == "origin twice":
            for r in doc["runs"]:
                r["origin"] = {"database": "0123456789abcdef0123456789abcdef", "job": 5}
        elif kind == "scene":
            doc["runs"][run]["scene"]["S"] = rng.choice([-1, "x", 2.5])
        elif kind == "summary status":
            doc["runs"][run]["summary"]["status"] = rng.choice([{}, None, 5, [], True])
        elif kind == "npy":
            doc["runs"][run]["artifacts"] = [{"name": "spacetime.npy", "content_type": "x", "size": 80,
                                              "data": "k05VTVBZAQB2AHsnZGVzY3InOiAnPGY0JywgJ2ZvcnRyYW5fb3JkZXInOiBGYWxzZSwgJ3NoYXBlJzogKDEwOTk1MTE2Mjc3NzYsIDEwNzM3NDE4MjQpLCB9ICAgICAg"}]
        elif kind == "request":
            doc["sweep"]["request"] = {"points": json.loads(deep(rng.choice([70, 200])))}
        elif kind == "empty runs":
            doc["runs"] = [{}] * rng.randint(1, 1000)
        elif kind == "label nul":
            doc["runs"][run]["human_label"] = {"label": "a", "reason": "a\u0000b", "by": "x", "at": 1}
        else:
            doc["version"] = rng.choice([2, -1, "1"])
        body = json.dumps(doc).encode()
    return "import " + kind, request("POST", "/api/v1/imports", JSON + auth(S), body)


def case_label():
    method = rng.choice(["PUT", "DELETE"])
    body = rng.choice([
        {"label": rng.choice(["z", "", 1, None, "ab"]), "reason": "r", "by": "x"},
        {"label": "a", "reason": rng.choice(["a\u0000b", "\u001b[2J", "", 7]), "by": "x"},
        {"label": "a", "reason": "r", "by": rng.choice(["a\nb", "", "\u0000"])},
        {"reason": "\u0000", "by": "x"},
        {"label": "a", "reason": "r", "by": "x", "token": "forged"},
    ])
    token = rng.choice([S, S, W, "guess"])
    # The job has no result: a correct label is a 409, a malformed one 422, a wrong token 401/403.
    return "label", request(method, "/api/v1/jobs/%d/label" % JOB, JSON + auth(token),
                            json.dumps(body))


def case_checkpoint():
    fields = {"lease_token": LIVE if rng.random() < 0.3 else "stale", "step": "10", "eps": "0.1",
              "checkpoint": "bytes"}
    bad = rng.choice(["eps", "step", "missing", "unknown"])
    if bad == "eps":
        fields["eps"] = rng.choice([" 0.5", "0x1p-3", "1e-400", "nan", "2", "-0.1", ""])
    elif bad == "step":
        fields["step"] = rng.choice(["-1", "1.5", "99999999999999999999", " 3", "x"])
    elif bad == "missing":
        del fields[rng.choice(list(fields))]
    else:
        fields["extra"] = "1"
    body = multipart([(k.encode(), None, v.encode()) for k, v in fields.items()], "ckpt")
    token = W if rng.random() < 0.9 else S
    return "checkpoint " + bad, request("POST", "/api/v1/jobs/%d/checkpoint" % JOB,
                                        [("Content-Type", "multipart/form-data; boundary=ckpt")]
                                        + auth(token), body)


def case_headers():
    """Heads that RFC 9110/9112 call malformed or ambiguous: each a 400, whatever follows."""
    kind = rng.choice(["origin twice", "authorization twice", "length twice", "host twice",
                       "no host", "obs-fold", "no colon", "space before colon", "bare lf"])
    body = b'{"name": "x", "points": [%s]}' % POINT.encode()
    base = [b"POST /api/v1/sweeps HTTP/1.1", b"Host: " + HOST.encode(), b"Connection: close",
            b"Content-Type: application/json", b"Authorization: Bearer " + S.encode(),
            b"Content-Length: %d" % len(body)]
    if kind == "origin twice":
        base += [b"Origin: http://" + HOST.encode(), b"Origin: http://evil.example"]
    elif kind == "authorization twice":
        base += [b"Authorization: Bearer guess"]
    elif kind == "length twice":
        base += [b"Content-Length: 2"]
    elif kind == "host twice":
        base += [b"Host: evil.example"]
    elif kind == "no host":
        base.pop(1)
    elif kind == "obs-fold":
        base += [b"X-Folded: a", b" continued"]
    elif kind == "no colon":
        base += [b"X-No-Colon"]
    elif kind == "space before colon":
        base += [b"Host : 127.0.0.1"]
    else:
        return "headers " + kind, b"\r\n".join(base[:3]) + b"\nX-A: 1\r\n\r\n"
    return "headers " + kind, b"\r\n".join(base) + b"\r\n\r\n" + body


CASES = [case_path_utf8, case_raw_path_bytes, case_query, case_header_utf8, case_json_string_utf8,
         case_deep_nesting, case_huge_numbers, case_oversized, case_chunked, case_content_type,
         case_origin, case_tokens, case_multipart, case_malformed_line, case_import, case_label,
         case_checkpoint, case_headers]

before = db_state()
start = time.time()
sent = 0
by_kind = {}
while sent < MAX_REQUESTS and time.time() - start < TIME_BUDGET:
    kind, raw = rng.choice(CASES)()
    try:
        answer = exchange(raw)
    except socket.timeout:
        fail("request %d (%s) had no answer within 10 s: %r" % (sent + 1, kind, raw[:300]))
    sent += 1
    by_kind[kind.split()[0]] = by_kind.get(kind.split()[0], 0) + 1
    check(health_ok(), "request %d (%s) left the server unable to answer /health: %r"
          % (sent, kind, raw[:300]))
    if answer is None:
        # Only a request the server could not even read may go unanswered (a line it cut).
        check(kind == "request line", "request %d (%s) got no answer: %r" % (sent, kind, raw[:300]))
        continue
    status, headers, body = answer
    check(400 <= status < 500, "request %d (%s) answered %d, not 4xx: %r -> %r"
          % (sent, kind, status, raw[:300], body[:300]))
    if kind.startswith("headers"):
        check(status == 400, "request %d (%s) answered %d, not 400" % (sent, kind, status))
    try:
        err = json.loads(body)["error"]
    except (ValueError, KeyError, TypeError):
        fail("request %d (%s): the answer is not a JSON error: %r -> %r" % (sent, kind, raw[:200], body[:300]))
    check(isinstance(err.get("field"), str) and err["field"] and err.get("message"),
          "request %d (%s): the error names no field: %r" % (sent, kind, body[:300]))
    if sent % 200 == 0:
        check(db_state() == before, "the database changed by request %d (%s)" % (sent, kind))
elapsed = time.time() - start
check(sent >= MIN_REQUESTS, "only %d requests in %.0f s" % (sent, elapsed))
check(db_state() == before, "the malformed requests changed the database or the artifacts")
with open(os.path.join(env.dir, "server.log"), "rb") as f:
    log = f.read()
check(b"\x1b" not in log, "an escape character reached the log")
for line in log.split(b"\n"):
    check(not line or line[:2] == b"20", "a log line that the server did not write: %r" % line[:200])
print("%d malformed requests in %.1f s, each answered 4xx with a JSON error; by kind: %s"
      % (sent, elapsed, by_kind))
