"""Bodies far beyond an endpoint's limit cost the server nothing: four parallel 50 MB sweep
requests with the right token, four without a token and four to the worker endpoints are
refused from their headers (413, 401) and never read, and the server's peak resident memory
(VmHWM) stays below 200 MB. Then a sweep still goes through."""
import socket
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
