"""Starting and stopping the programs as a scheduler or an operator would: a second server on
a busy port exits 1 naming the port (it never shares it); a second server (or --import) on a
database another server holds exits 1 naming the holder's pid, and deletes nothing (not even a
folder the start-up clean-up would remove); --host that is not a loopback address
(or does not resolve) needs tokens; a worker that never reaches its server exits 3; a worker
killed with -9 leaves a work folder that the next worker beside it removes."""
import os
import signal
import socket
import subprocess
import time

import e2e_lib
from e2e_lib import Env, TINY, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "start")
env.start_server("--lease-seconds", "2", "--rescue-interval", "0.2")
server_bin = os.path.join(env.bin, "compaction-server")
worker_bin = os.path.join(env.bin, "compaction-worker")

second = subprocess.run([server_bin, "--db", os.path.join(env.dir, "other.db"), "--port",
                         str(env.port)], capture_output=True, text=True, timeout=30)
check(second.returncode == 1, "a second server on a busy port exits 1, got %d" % second.returncode)
check("cannot listen" in second.stderr + second.stdout and str(env.port) in second.stderr + second.stdout,
      "it says the port is taken: %s" % (second.stderr + second.stdout))
check(env.get("/api/v1/health")["status"] == "ok", "the first server still answers")

# One server per database: the second start takes nothing, cleans nothing, serves nothing.
pending = os.path.join(env.db + ".artifacts", "upload-being-written")
os.makedirs(pending)
with open(os.path.join(pending, "frames.csv"), "w") as f:
    f.write("eps\n")
export = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "studies", "phase_map",
                      "results", "example-c-reference.export.json")
for extra in [["--port", "0"], ["--import", export]]:
    same_db = subprocess.run([server_bin, "--db", env.db] + extra, capture_output=True, text=True,
                             timeout=30)
    said = same_db.stderr + same_db.stdout
    check(same_db.returncode == 1, "a second server on a held database exits 1, got %d: %s"
          % (same_db.returncode, said))
    check("in use by another compaction-server (pid %d" % env.server.pid in said,
          "it names the holder: %s" % said)
check(os.path.exists(os.path.join(pending, "frames.csv")), "the second start deleted a folder")
check(env.get("/api/v1/health")["status"] == "ok", "the first server still answers")

for host in ["127.evil.invalid", "0.0.0.0"]:
    r = subprocess.run([server_bin, "--db", os.path.join(env.dir, "h.db"), "--host", host,
                        "--port", "0"], capture_output=True, text=True, timeout=30)
    check(r.returncode == 2 and "--host" in r.stderr,
          "--host %s without tokens exits 2 naming --host: %d %s" % (host, r.returncode, r.stderr))

# A port nothing listens on.
s = socket.socket()
s.bind(("127.0.0.1", 0))
dead_port = s.getsockname()[1]
s.close()
r = subprocess.run([worker_bin, "--server", "http://127.0.0.1:%d" % dead_port, "--idle-exit", "1",
                    "--poll-interval", "0.2", "--work-dir", os.path.join(env.dir, "w-dead")],
                   capture_output=True, text=True, timeout=30)
check(r.returncode == 3, "a worker that never reached its server exits 3, got %d: %s"
      % (r.returncode, r.stderr[-500:]))

# kill -9 in the middle of a job: its folder stays; the next worker in the same place clears it.
tmp = os.path.join(env.dir, "tmp")
os.makedirs(tmp)
long_scene = dict(TINY, eps_end=0.3)
env.submit({"name": "long", "points": [{"S": 0.01, "R": 1e-3, "phi": 0.4}], "numerics": long_scene})
victim = subprocess.Popen([worker_bin, "--server", env.url, "--poll-interval", "0.2"],
                          env=dict(os.environ, TMPDIR=tmp), stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL)
e2e_lib._procs.append(victim)  # killed at exit if the test fails before it does
folder = os.path.join(tmp, "compaction-worker-%d" % victim.pid)
env.wait_for(lambda: os.path.isdir(folder) and any(n.startswith("job-") for n in os.listdir(folder)),
             30, "the worker's job folder")
victim.send_signal(signal.SIGKILL)
victim.wait()
check(os.path.isdir(folder), "kill -9 leaves the folder")
survivor = subprocess.Popen([worker_bin, "--server", env.url, "--poll-interval", "0.2",
                             "--idle-exit", "2"], env=dict(os.environ, TMPDIR=tmp),
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
e2e_lib._procs.append(survivor)
env.wait_for(lambda: not os.path.exists(folder), 20, "the next worker to remove the dead one's folder")
own = os.path.join(tmp, "compaction-worker-%d" % survivor.pid)
check(os.path.isdir(own), "while its own folder stays")
check(survivor.wait(120) == 0, "the second worker finishes the job and exits 0")
check(not os.path.exists(own), "and removes its own folder when it ends")
print("busy port, loopback check, exit code 3 and the scratch folders: as documented")
