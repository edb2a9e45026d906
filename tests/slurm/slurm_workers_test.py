"""Workers under a real Slurm of one node on loopback, started with scripts/slurm/submit-workers.sh
(docs/cluster.md). The test starts its own munged (own key and socket), slurmctld and slurmd (own
ports, state, spool, pid and log files) in a temporary folder, and a real server with tokens on a
temporary database; it stops every daemon and removes the folder at exit, also after a failure.
- A sweep at the fast preset is done by a job array of two workers, which end by themselves
  (--idle-exit) with exit code 0; the server's records name them after the array job and task.
- An array pointed at a port where nothing listens ends FAILED with the worker's exit code 3.
- SIGTERM before the time limit reaches the workers, sent as Slurm sends it: to the srun tasks
  of one job of two (scancel --signal=TERM, what --signal=TERM@S sends), then to the batch shell
  of an array task (scancel --batch --signal=TERM, what --signal=B:TERM@S sends). The worker
  running the job gives its lease back and every worker exits 0.
- Tokens: a token file others can read is refused; the worker token reaches the workers'
  environment from its file; no process has a token on its command line, and neither squeue,
  scontrol nor slurmctld's saved job state (scripts, arguments, environments) holds one.
Needs root: the daemons run as root (SlurmUser=root); scripts/install-slurm.sh installs the
packages when they are missing."""
import atexit
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "e2e"))
import e2e_lib  # noqa: E402
from e2e_lib import Env, bin_dir_from_args, check, fail  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SUBMIT = os.path.join(ROOT, "scripts", "slurm", "submit-workers.sh")
BUDGET_SECONDS = 240  # the whole test, cleanup included, ends before ctest's TIMEOUT
TERMINAL = {"COMPLETED", "FAILED", "CANCELLED", "TIMEOUT", "NODE_FAIL", "OUT_OF_MEMORY",
            "PREEMPTED", "BOOT_FAIL", "DEADLINE"}


def on_alarm(*_):
    fail("the test's budget of %d s is used up" % BUDGET_SECONDS)


signal.signal(signal.SIGALRM, on_alarm)
signal.alarm(BUDGET_SECONDS)

if os.geteuid() != 0:
    fail("needs root: slurmctld, slurmd and munged run as root here (SlurmUser=root)")
if not all(shutil.which(p) for p in ("slurmctld", "slurmd", "sbatch", "scontrol", "munged")):
    subprocess.run([os.path.join(ROOT, "scripts", "install-slurm.sh")], check=True)

env = Env(bin_dir_from_args(), "slurm")
os.chmod(env.dir, 0o755)  # munged wants every folder above its socket searchable by all


def path(*parts):
    return os.path.join(env.dir, *parts)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def run(*cmd):
    """A Slurm client command against this cluster; its output, or a failure naming it."""
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=env.dir)
    check(p.returncode == 0, "%s -> exit %d: %s" % (" ".join(cmd), p.returncode, p.stdout + p.stderr))
    return p.stdout


def tail(name):
    if not os.path.exists(name):
        return "(no %s)" % name
    with open(name, errors="replace") as f:
        return name + ":\n" + f.read()[-3000:]


daemons = []  # (name, Popen), stopped in reverse order at exit


def start_daemon(name, *cmd):
    log = open(path("log", name + ".out"), "w")
    p = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=env.dir)
    e2e_lib._procs.append(p)  # killed with the other processes if a stop below fails
    daemons.append((name, p))
    return p


def stop_cluster():
    """Cancels every job of this cluster, waits for them to end, then stops the daemons."""
    ctld = dict(daemons).get("slurmctld")
    if ctld is not None and ctld.poll() is None:
        subprocess.run(["scancel", "--user=root"], capture_output=True)
        deadline = time.time() + 30
        while time.time() < deadline:
            q = subprocess.run(["squeue", "-h", "-o", "%i"], capture_output=True, text=True)
            if q.returncode != 0 or not q.stdout.strip():
                break
            time.sleep(0.2)
    for name, p in reversed(daemons):
        if p.poll() is None:
            p.terminate()
            try:
                p.wait(15)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


atexit.register(stop_cluster)  # registered after Env: runs before the folder is removed

# --- munge: a key of its own, a socket of its own ---
for d in ("munge", "munge-key", "log", "state", "spool", "tmp"):
    os.makedirs(path(d), exist_ok=True)
os.chmod(path("munge-key"), 0o700)
with open(path("munge-key", "munge.key"), "wb") as f:
    f.write(os.urandom(1024))
os.chmod(path("munge-key", "munge.key"), 0o600)
munge_socket = path("munge", "munge.socket")
munged = start_daemon("munged", "munged", "--foreground", "--socket=" + munge_socket,
                      "--key-file=" + path("munge-key", "munge.key"),
                      "--pid-file=" + path("munge", "munged.pid"),
                      "--seed-file=" + path("munge", "munged.seed"),
                      "--log-file=" + path("log", "munged.log"))
deadline = time.time() + 20
while not os.path.exists(munge_socket):
    check(munged.poll() is None, "munged exited at start: " + tail(path("log", "munged.out")))
    check(time.time() < deadline, "munged did not create its socket")
    time.sleep(0.05)

# --- slurm.conf: one node on loopback with what slurmd finds on this machine ---
hardware = subprocess.run(["slurmd", "-C"], capture_output=True, text=True).stdout
cpus = int(re.search(r"\bCPUs=(\d+)", hardware).group(1))
memory = int(re.search(r"\bRealMemory=(\d+)", hardware).group(1))
conf = path("slurm.conf")
with open(conf, "w") as f:
    f.write("""ClusterName=compaction-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={munge_socket}
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/slurmctld.pid
SlurmdPidFile={dir}/slurmd.pid
SlurmctldLogFile={dir}/log/slurmctld.log
SlurmdLogFile={dir}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
ReturnToService=2
NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory} State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
""".format(ctld_port=free_port(), slurmd_port=free_port(), munge_socket=munge_socket,
           dir=env.dir, cpus=cpus, memory=memory))
os.environ["SLURM_CONF"] = conf           # every client command, and the jobs, use this cluster
os.environ["TMPDIR"] = path("tmp")        # the workers' scratch folders stay in the test's folder
ctld = start_daemon("slurmctld", "slurmctld", "-D", "-f", conf)
slurmd = start_daemon("slurmd", "slurmd", "-D", "-N", "localhost", "-f", conf)
deadline = time.time() + 60
while True:
    for name, p in daemons:
        check(p.poll() is None, "%s exited at start: %s\n%s" % (
            name, tail(path("log", name + ".out")), tail(path("log", name + ".log"))))
    q = subprocess.run(["sinfo", "-h", "-n", "localhost", "-o", "%T"], capture_output=True,
                       text=True)
    if q.returncode == 0 and q.stdout.strip() == "idle":
        break
    check(time.time() < deadline, "the node is not idle: %s%s\n%s" % (
        q.stdout, q.stderr, tail(path("log", "slurmctld.log"))))
    time.sleep(0.2)


def slurm_tasks(job_id):
    """{task: (JobState, ExitCode)} of a job (one entry per array task), from scontrol."""
    out = run("scontrol", "show", "job", "-o", job_id)
    tasks = {}
    for line in out.splitlines():
        fields = dict(re.findall(r"(\w+)=(\S*)", line))
        tasks[fields.get("ArrayTaskId", "0")] = (fields["JobState"], fields["ExitCode"])
    return tasks


def wait_slurm_job_end(job_id, n_tasks, timeout, what):
    deadline = time.time() + timeout
    while time.time() < deadline:
        tasks = slurm_tasks(job_id)
        if len(tasks) == n_tasks and all(s in TERMINAL for s, _ in tasks.values()):
            return tasks
        time.sleep(0.2)
    outputs = "\n".join(tail(path(f)) for f in sorted(os.listdir(env.dir)) if f.endswith(".out"))
    fail("timed out after %d s waiting for %s (job %s) to end: %s\n%s\n%s" % (
        timeout, what, job_id, slurm_tasks(job_id), outputs, tail(path("log", "slurmd.log"))))


def submit_workers(*args):
    p = subprocess.run([SUBMIT, "--bin", env.bin, "--time", "10", *args], capture_output=True,
                       text=True, cwd=env.dir)
    check(p.returncode == 0 and re.fullmatch(r"\d+\n", p.stdout),
          "submit-workers.sh %s -> exit %d: %s%s" % (" ".join(args), p.returncode, p.stdout, p.stderr))
    return p.stdout.strip()


SUBMIT_TOKEN = "submit-" + os.urandom(12).hex()
WORKER_TOKEN = "worker-" + os.urandom(12).hex()
token_file = path("worker.token")
with open(os.open(token_file, os.O_WRONLY | os.O_CREAT, 0o600), "w") as f:
    f.write(WORKER_TOKEN + "\n")
# The server takes its tokens from the environment, as docs/cluster.md advises; the launcher
# must keep them out of the environment that sbatch stores with each job.
os.environ["COMPACTION_SUBMIT_TOKEN"] = SUBMIT_TOKEN
os.environ["COMPACTION_WORKER_TOKEN"] = WORKER_TOKEN
env.start_server()
readable = path("readable.token")
with open(readable, "w") as f:
    f.write(WORKER_TOKEN + "\n")
os.chmod(readable, 0o644)
p = subprocess.run([SUBMIT, "--bin", env.bin, "--time", "10", "--server", env.url, "--workers", "1",
                    "--token-file", readable], capture_output=True, text=True, cwd=env.dir)
check(p.returncode == 2 and "chmod 600" in p.stderr and not p.stdout,
      "a token file others can read is refused before sbatch: exit %d, %s" % (p.returncode, p.stderr))
t0 = time.time()

# --- a sweep done by a job array that ends by itself ---
points = [{"S": S, "R": 1e-3, "phi": 0.4} for S in (0.1, 0.2, 0.4)]
sweep = env.submit({"name": "slurm", "points": points, "numerics": {"preset": "fast"}},
                   SUBMIT_TOKEN)
array = submit_workers("--server", env.url, "--workers", "2", "--token-file", token_file,
                       "--idle-exit", "3", "--output", path("array-%A_%a.out"),
                       "--", "--poll-interval", "0.5")
env.wait_sweep_done(sweep["id"], 150)
tasks = wait_slurm_job_end(array, 2, 60, "the worker array")
check(all(t == ("COMPLETED", "0:0") for t in tasks.values()),
      "every array task ends COMPLETED with exit code 0 (idle exit), got %s" % tasks)
jobs = env.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"]
check(len(jobs) == 3 and all(j["state"] == "succeeded" for j in jobs),
      "the sweep's 3 jobs succeeded: %s" % [(j["id"], j["state"]) for j in jobs])
names = {j["result"]["worker"] for j in jobs}
check(all(re.fullmatch(r"slurm-%s_[01]@localhost" % array, n) for n in names),
      "the workers are named slurm-%s_TASK@localhost, got %s" % (array, sorted(names)))
array_seconds = time.time() - t0

# --- an array whose server never answers fails with the worker's exit code ---
unreachable = submit_workers("--server", "http://127.0.0.1:%d" % free_port(), "--workers", "1",
                             "--idle-exit", "1", "--output", path("unreachable-%A_%a.out"))
tasks = wait_slurm_job_end(unreachable, 1, 60, "the array pointed at nothing")
check(tasks == {"0": ("FAILED", "3:0")},
      "a worker that never reached its server ends FAILED with exit code 3, got %s" % tasks)
with open(path("unreachable-%s_0.out" % unreachable), errors="replace") as f:
    check("never answered" in f.read(), "the task's output says the server never answered")

# --- SIGTERM through the batch shell and srun to every task; the token on no command line ---
long_sweep = env.submit({"name": "slurm-term", "points": [{"S": 3e-3, "R": 1e-3, "phi": 0.4}],
                         "numerics": {"preset": "default"}}, SUBMIT_TOKEN)
n_tasks = min(2, cpus)
srun_job = submit_workers("--server", env.url, "--workers", str(n_tasks), "--srun",
                          "--token-file", token_file, "--idle-exit", "0",
                          "--output", path("srun-%j.out"), "--", "--poll-interval", "0.5")
job_id = env.get("/api/v1/jobs?sweep=%d" % long_sweep["id"])["jobs"][0]["id"]
job = env.wait_for(lambda: (lambda j: j if j["state"] == "running" else None)(
    env.get("/api/v1/jobs/%d" % job_id)), 60, "the long job to run under srun")
check(re.fullmatch(r"slurm-%s-task[01]@localhost" % srun_job, job["worker"] or ""),
      "an srun worker is named slurm-%s-taskPROCID@localhost, got %s" % (srun_job, job["worker"]))


def srun_workers():
    """The srun job's workers now running, name -> (pid, argv, environ) (a worker's forked child,
    before its exec, looks alike); fails on any process with a token on its command line."""
    workers = {}
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                argv = f.read().split(b"\0")
            with open("/proc/%s/environ" % pid, "rb") as f:
                environ = f.read().split(b"\0")
        except OSError:
            continue  # a process that ended meanwhile
        check(all(WORKER_TOKEN.encode() not in a and SUBMIT_TOKEN.encode() not in a for a in argv),
              "process %s has a token on its command line: %s" % (pid, argv))
        name = argv[argv.index(b"--name") + 1].decode() if b"--name" in argv[:-1] else ""
        if argv[0].endswith(b"/compaction-worker") and name.startswith("slurm-%s-task" % srun_job):
            workers[name] = (pid, argv, environ)
    return workers


# One task's worker leased the job; the other may still be starting (srun starts the tasks side
# by side, and a loaded machine can hold one back for seconds).
expected = {"slurm-%s-task%d@localhost" % (srun_job, i) for i in range(n_tasks)}
deadline = time.time() + 30
while True:
    workers = srun_workers()
    if set(workers) == expected or time.time() >= deadline:
        break
    time.sleep(0.2)
check(set(workers) == expected, "the srun workers %s run within 30 s, found %s"
      % (sorted(expected), sorted(workers)))
for pid, argv, environ in workers.values():
    check(("COMPACTION_WORKER_TOKEN=" + WORKER_TOKEN).encode() in environ,
          "worker %s has the token from the file in its environment" % pid)
shown = run("squeue", "-h", "-o", "%all") + run("scontrol", "show", "job", "-d", srun_job)
check(WORKER_TOKEN not in shown and SUBMIT_TOKEN not in shown, "squeue and scontrol show no token")
stored = []  # what slurmctld keeps of the jobs: their scripts, arguments and environments
for folder, _, files in os.walk(path("state")):
    for name in files:
        with open(os.path.join(folder, name), "rb") as f:
            data = f.read()
        if WORKER_TOKEN.encode() in data or SUBMIT_TOKEN.encode() in data:
            stored.append(os.path.join(folder, name))
job_state = path("state", "hash.%d" % (int(srun_job) % 10), "job." + srun_job)
check(os.path.exists(os.path.join(job_state, "environment")),
      "slurmctld keeps the job's environment in %s" % job_state)
check(not stored, "no token in slurmctld's state: %s" % stored)
run("scancel", "--signal=TERM", srun_job)  # every step's tasks, not the batch shell
tasks = wait_slurm_job_end(srun_job, 1, 60, "the srun job after SIGTERM")
check(tasks == {"0": ("COMPLETED", "0:0")},
      "the srun job ends COMPLETED with exit code 0 after SIGTERM, got %s" % tasks)


def check_released(worker_pattern):
    job = env.get("/api/v1/jobs/%d" % job_id)
    check(job["state"] == "queued" and job["attempts"] == 0,
          "the lease was given back: queued, attempt not counted; got %s, %d, events %s" % (
              job["state"], job["attempts"], job["events"]))
    last = job["events"][-1]
    check(last["kind"] == "released" and re.fullmatch(worker_pattern, last["worker"] or ""),
          "the last event is the release by %s, got %s" % (worker_pattern, last))


check_released(r"slurm-%s-task[01]@localhost" % srun_job)
with open(path("srun-%s.out" % srun_job), errors="replace") as f:
    stopped = f.read().count("stopped by signal")
check(stopped == n_tasks, "every srun task was stopped by the signal (%d of %d)" % (stopped, n_tasks))

term_array = submit_workers("--server", env.url, "--workers", "1", "--token-file", token_file,
                            "--idle-exit", "0", "--output", path("term-%A_%a.out"),
                            "--", "--poll-interval", "0.5")
env.wait_for(lambda: env.get("/api/v1/jobs/%d" % job_id)["state"] == "running", 60,
             "the long job to run in the array task")
run("scancel", "--batch", "--signal=TERM", term_array)  # the batch shell only
tasks = wait_slurm_job_end(term_array, 1, 60, "the array task after SIGTERM")
check(tasks == {"0": ("COMPLETED", "0:0")},
      "the array task ends COMPLETED with exit code 0 after SIGTERM, got %s" % tasks)
check_released(r"slurm-%s_0@localhost" % term_array)
print("ok (array sweep %.1f s, %d CPUs)" % (array_seconds, cpus))
