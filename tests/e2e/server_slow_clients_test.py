"""Slow clients cannot stall the server: 50 slowloris sockets, each sending one header line
every 3 s, and 10 sockets that open and say nothing; meanwhile /api/v1/health answers within
1 s every time. The server cuts the slow ones at its header deadline (10 s), and none of them
ever gets an answer it did not earn (a 400 or a close, never a 200)."""
import socket
import threading
import time
import urllib.request

from e2e_lib import Env, bin_dir_from_args, check

env = Env(bin_dir_from_args(), "slow-clients")
env.start_server()
stop = threading.Event()
outcomes = []


def slowloris(i):
    s = socket.create_connection(("127.0.0.1", env.port), timeout=30)
    outcome = "still open"
    try:
        s.sendall(b"GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n")
        n = 0
        while not stop.is_set():
            s.settimeout(3.0)
            try:
                data = s.recv(4096)
                outcome = "answered " + data.split(b"\r\n", 1)[0].decode(errors="replace") if data else "closed"
                break
            except socket.timeout:
                pass
            try:
                s.sendall(b"X-Slow-%d-%d: 1\r\n" % (i, n))
            except (BrokenPipeError, ConnectionResetError):
                outcome = "closed"
                break
            n += 1
    except (ConnectionResetError, BrokenPipeError):
        outcome = "closed"
    finally:
        s.close()
    outcomes.append(outcome)


def silent():
    s = socket.create_connection(("127.0.0.1", env.port), timeout=30)
    try:
        s.settimeout(20)
        data = s.recv(4096)
        outcomes.append("closed" if not data else "answered " + data.split(b"\r\n", 1)[0].decode())
    except (ConnectionResetError, socket.timeout):
        outcomes.append("closed")
    finally:
        s.close()


threads = [threading.Thread(target=slowloris, args=(i,)) for i in range(50)]
threads += [threading.Thread(target=silent) for _ in range(10)]
for t in threads:
    t.start()
time.sleep(0.5)
worst = 0.0
start = time.time()
while time.time() - start < 14:
    t0 = time.time()
    with urllib.request.urlopen(env.url + "/api/v1/health", timeout=5) as r:
        check(r.status == 200, "health answered %d" % r.status)
    worst = max(worst, time.time() - t0)
    check(worst < 1.0, "/api/v1/health took %.2f s with 60 slow clients connected" % worst)
    time.sleep(0.2)
stop.set()
for t in threads:
    t.join(30)
cut = sum(1 for o in outcomes if o == "closed" or o.startswith("answered HTTP/1.1 400"))
check(cut == 60, "the server cut every slow client by its header deadline: %s" % sorted(set(outcomes)))
print("health answered within %.3f s at worst beside 60 slow clients; all 60 cut by the server"
      % worst)
