"""Slow clients cannot starve the server: 1 000 sockets of each kind, held open for 30 s (each
one the server cuts is opened again at once):
  - headers: a request head sent one header line every 0.5 s (slowloris);
  - body:    POST /api/v1/sweeps/estimate with Content-Length 1000000 and one byte every 0.5 s
             (no token needed: the endpoint is open);
  - silent:  connected and saying nothing.
Meanwhile /api/v1/health, asked every 0.2 s on a new connection, answers 200 within 1 s every
time. The server cuts the slow ones (a 408 or a close, never an answer they did not earn): the
heads at their 10 s deadline, the bodies at the pace rule's (10 s of grace, then 16 KiB/s), the
silent ones at 10 s. One thread drives all the sockets (epoll), as an attacker's would."""
import resource
import selectors
import socket
import threading
import time
import urllib.request

from e2e_lib import Env, bin_dir_from_args, check

PER_KIND = 1000
DURATION = 30.0
TICK = 0.5

soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
resource.setrlimit(resource.RLIMIT_NOFILE, (hard, hard))
check(hard >= 3 * PER_KIND + 200, "this test needs %d open files, the limit is %d" % (3 * PER_KIND + 200, hard))

env = Env(bin_dir_from_args(), "slow-clients")
env.start_server()
host = b"Host: 127.0.0.1:%d\r\n" % env.port

OPENINGS = {
    "headers": b"GET /api/v1/health HTTP/1.1\r\n" + host,
    "body": b"POST /api/v1/sweeps/estimate HTTP/1.1\r\n" + host +
            b"Content-Type: application/json\r\nContent-Length: 1000000\r\n\r\n{",
    "silent": b"",
}


def drip(kind, n):
    if kind == "headers":
        return b"X-Slow-%d: 1\r\n" % n
    if kind == "body":
        return b" "
    return b""


sel = selectors.DefaultSelector()
stats = {kind: {"opened": 0, "cut": 0, "answers": {}} for kind in OPENINGS}
unearned = []


class Slow:
    def __init__(self, kind):
        self.kind = kind
        self.n = 0
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.setblocking(False)
        self.sock.connect_ex(("127.0.0.1", env.port))
        self.sent_opening = False
        sel.register(self.sock, selectors.EVENT_READ | selectors.EVENT_WRITE, self)
        stats[kind]["opened"] += 1

    def close(self, answer):
        try:
            sel.unregister(self.sock)
        except (KeyError, ValueError):
            pass
        self.sock.close()
        s = stats[self.kind]
        s["cut"] += 1
        if answer:
            status = answer.split(b"\r\n", 1)[0].decode(errors="replace")
            s["answers"][status] = s["answers"].get(status, 0) + 1
            if b" 408 " not in answer[:16]:
                unearned.append((self.kind, status))

    def tick(self):
        """Sends the next byte; False when the server has closed the socket."""
        data = drip(self.kind, self.n)
        self.n += 1
        if not self.sent_opening or not data:
            return True
        try:
            self.sock.send(data)
        except (BlockingIOError, InterruptedError):
            pass
        except OSError:
            self.close(b"")
            return False
        return True


def attack(stop):
    live = set()
    for kind in OPENINGS:
        for _ in range(PER_KIND):
            live.add(Slow(kind))
    next_tick = time.time() + TICK
    while not stop.is_set():
        for key, events in sel.select(timeout=max(0.0, next_tick - time.time())):
            c = key.data
            if events & selectors.EVENT_WRITE and not c.sent_opening:
                c.sent_opening = True
                sel.modify(c.sock, selectors.EVENT_READ, c)
                if OPENINGS[c.kind]:
                    try:
                        c.sock.send(OPENINGS[c.kind])
                    except OSError:
                        pass
            if events & selectors.EVENT_READ:
                try:
                    answer = c.sock.recv(4096)
                except (BlockingIOError, InterruptedError):
                    continue
                except OSError:
                    answer = b""
                c.close(answer)
                live.discard(c)
                live.add(Slow(c.kind))  # the attacker opens another at once
        if time.time() >= next_tick:
            next_tick += TICK
            for c in list(live):
                if not c.tick():
                    live.discard(c)
                    live.add(Slow(c.kind))
    for c in live:
        try:
            sel.unregister(c.sock)
        except (KeyError, ValueError):
            pass
        c.sock.close()


stop = threading.Event()
attacker = threading.Thread(target=attack, args=(stop,))
attacker.start()
time.sleep(2.0)  # every socket connected and its opening sent

worst, asked = 0.0, 0
start = time.time()
while time.time() - start < DURATION:
    t0 = time.time()
    with urllib.request.urlopen(env.url + "/api/v1/health", timeout=15) as r:
        check(r.status == 200, "health answered %d" % r.status)
    took = time.time() - t0
    worst = max(worst, took)
    asked += 1
    check(took < 1.0, "/api/v1/health took %.2f s beside %d slow sockets of each kind (%.0f s in)"
          % (took, PER_KIND, time.time() - start))
    time.sleep(0.2)
stop.set()
attacker.join(30)

for kind, s in stats.items():
    # Within 30 s every first socket of a kind passed its deadline, so at least 1 000 were cut.
    check(s["cut"] >= PER_KIND, "the server cut only %d of the %s sockets in %.0f s: %s"
          % (s["cut"], kind, DURATION, s))
check(not unearned, "slow clients got answers they did not earn: %s" % unearned[:5])
check(env.server.poll() is None, "the server died")
print("health answered %d times, within %.3f s at worst, beside %d slow sockets of each kind; "
      "cut by the server: %s" % (asked, worst, PER_KIND,
                                 {k: (s["cut"], s["answers"]) for k, s in stats.items()}))
