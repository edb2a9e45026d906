"""The images of docker/ built and run with Debian's podman, the server and two workers through
docker/compose.yaml with podman-compose (docs/cluster.md, "Containers"):
- podman gets a configuration and a storage of its own in a temporary folder
  (scripts/podman-conf.sh): nothing of the machine's podman setup is assumed or touched;
- the source is the committed HEAD (git archive; --worktree: the working tree's tracked and not
  ignored files instead), and the images are built from it by scripts/container-images.sh, on a
  base image made with debootstrap from Debian's packages (its root is saved between runs in
  /var/tmp/compaction-container-base for up to 7 days: only Debian's packages, updated by the
  build's apt-get update);
- `podman-compose build` then takes every layer from the cache: the compose file's build section
  builds the same images as the script;
- `podman-compose up` starts the server (its port on loopback, tokens from the environment, the
  database in a named volume) and two workers that reach it by its service name;
  /api/v1/health reports the source revision of HEAD, and the worker image's runner reports it
  too; both workers ask the server for work;
- a sweep at the fast preset (3 points) is done by the workers: every job succeeded, its result
  names the revision and its artifacts download from the server;
- `podman-compose stop` stops every container with SIGTERM, and each exits 0 (the workers give
  their leases back, the server closes its database); `down` removes them, the network and the
  volume. At exit, also after a failure, the containers, images and the temporary folder go.
Prints the time of each step and the images' sizes. Needs root (rootful podman, debootstrap);
scripts/install-podman.sh installs podman, podman-compose, runc, netavark, aardvark-dns, iptables and
debootstrap when missing. Fails, never skips, when something is missing.
usage: container_test.py [--worktree]"""
import atexit
import json
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "e2e"))
from e2e_lib import Env, check, fail  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
BUDGET_SECONDS = 1700  # the whole test, cleanup included, ends before ctest's TIMEOUT (1800 s)
SUBMIT_TOKEN = secrets.token_hex(16)
WORKER_TOKEN = secrets.token_hex(16)
T0 = time.time()
times = []  # (step, seconds)


def on_alarm(*_):
    fail("the test's budget of %d s is used up" % BUDGET_SECONDS)


signal.signal(signal.SIGALRM, on_alarm)
signal.alarm(BUDGET_SECONDS)

worktree = sys.argv[1:] == ["--worktree"]
if sys.argv[1:] not in ([], ["--worktree"]):
    print("usage: %s [--worktree]" % sys.argv[0], file=sys.stderr)
    sys.exit(2)
if os.geteuid() != 0:
    fail("needs root: rootful podman and debootstrap")


def run(cmd, env=None, what=None, quiet=False):
    """Runs cmd in a process group of its own; its output, or a failure that shows it. When the
    test ends first (its budget, SIGTERM), the whole group is killed (a build's podman too)."""
    t = time.time()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env,
                         cwd=ROOT, start_new_session=True)
    try:
        out, err = p.communicate()
    except BaseException:
        os.killpg(p.pid, signal.SIGKILL)
        p.wait()
        raise
    if what:
        times.append((what, time.time() - t))
    check(p.returncode == 0, "%s -> exit %d:\n%s%s" % (" ".join(cmd), p.returncode, out[-6000:], err[-6000:]))
    if not quiet and out.strip():
        print(out.rstrip())
    return out


run([os.path.join(ROOT, "scripts", "install-podman.sh")], what="install-podman.sh")

# --- podman of its own: configuration and storage in a temporary folder ---------------------
workdir = tempfile.mkdtemp(prefix="compaction-container-", dir="/var/tmp")
os.chmod(workdir, 0o755)  # the containers' unprivileged user reads the layers and volumes below it
conf_dir = os.path.join(workdir, "podman")
project = "compaction-test-%d" % os.getpid()
src = os.path.join(workdir, "src")
compose = ["podman-compose", "-p", project, "-f", os.path.join(src, "docker", "compose.yaml")]
compose_up = False


def cleanup():
    if compose_up:
        subprocess.run(compose + ["down", "-v", "-t", "5"], env=env, capture_output=True, cwd=workdir)
    if os.path.exists(os.path.join(conf_dir, "containers.conf")):
        p = subprocess.run([os.path.join(ROOT, "scripts", "podman-conf.sh"), "--remove", conf_dir],
                           env=env, capture_output=True, text=True)
        if p.returncode != 0:
            print("cleanup: %s" % p.stderr, file=sys.stderr)
    if not os.environ.get("COMPACTION_KEEP_E2E"):
        shutil.rmtree(workdir, ignore_errors=True)


env = dict(os.environ)
atexit.register(cleanup)
signal.signal(signal.SIGTERM, lambda *_: sys.exit(1))
exports = run([os.path.join(ROOT, "scripts", "podman-conf.sh"), conf_dir], quiet=True)
for assignment in exports.split()[1:]:  # export CONTAINERS_CONF='...' CONTAINERS_STORAGE_CONF='...'
    name, value = assignment.split("=", 1)
    env[name] = value.strip("'")
check("CONTAINERS_CONF" in env and "CONTAINERS_STORAGE_CONF" in env, "podman-conf.sh: %s" % exports)
info = run(["podman", "info", "--format",
            "{{.Host.OCIRuntime.Name}} {{.Host.NetworkBackend}} {{.Store.GraphDriverName}} {{.Store.GraphRoot}}"],
           env=env, quiet=True).split()
check(info[3].startswith(conf_dir), "podman stores under %s, not %s" % (conf_dir, info[3]))
print("podman %s: runtime %s, network %s, storage %s in %s" % (
    run(["podman", "--version"], quiet=True).split()[-1], info[0], info[1], info[2], info[3]))

# --- the source: HEAD (or the working tree), and its revision ---------------------------------
git = ["git", "-c", "safe.directory=" + ROOT, "-C", ROOT]
revision = run(git + ["rev-parse", "--short=12", "HEAD"], quiet=True).strip()
os.makedirs(src)
if worktree:
    files = run(git + ["ls-files", "-z", "--cached", "--others", "--exclude-standard"], quiet=True)
    listing = os.path.join(workdir, "files")
    with open(listing, "w") as f:
        f.write(files)
    run(["tar", "-C", ROOT, "--null", "--ignore-failed-read", "-T", listing, "-cf",
         os.path.join(workdir, "src.tar")])
    if run(git + ["status", "--porcelain", "--untracked-files=no"], quiet=True).strip():
        revision += "-dirty"
else:
    run(["sh", "-c", 'git -c safe.directory="$1" -C "$1" archive --format=tar HEAD > "$2"', "sh",
         ROOT, os.path.join(workdir, "src.tar")])
run(["tar", "-C", src, "-xf", os.path.join(workdir, "src.tar")])
print("source: %s at %s" % ("the working tree" if worktree else "HEAD", revision))

# --- the images ---------------------------------------------------------------------------------
run([os.path.join(ROOT, "scripts", "container-images.sh"), "--src", src, "--revision", revision],
    env=env, what="container-images.sh (base and both images)")
images = {}
for name in ("compaction-server", "compaction-worker", "debian"):
    ref = "localhost/%s:%s" % (name, "bookworm" if name == "debian" else "latest")
    out = run(["podman", "image", "inspect", ref], env=env, quiet=True)
    images[name] = json.loads(out)[0]
for name in ("compaction-server", "compaction-worker"):
    labels = images[name]["Labels"] or {}
    check(labels.get("org.opencontainers.image.revision") == revision,
          "%s is labelled with revision %s: %s" % (name, revision, labels))
runner = run(["podman", "run", "--rm", "--entrypoint", "compaction-run", "localhost/compaction-worker",
              "--version"], env=env, quiet=True)
check(revision in runner, "the image's compaction-run --version names %s: %s" % (revision, runner))

compose_env = dict(env, COMPACTION_SUBMIT_TOKEN=SUBMIT_TOKEN, COMPACTION_WORKER_TOKEN=WORKER_TOKEN,
                   COMPACTION_BASE_IMAGE="localhost/debian:bookworm",
                   COMPACTION_SOURCE_REVISION=revision, COMPACTION_WORKERS="2")
with socket.socket() as s:
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
compose_env["COMPACTION_PORT"] = str(port)

built = {n: images[n]["Id"] for n in ("compaction-server", "compaction-worker")}
# podman-compose 1.0.3 exits 0 when a command it runs fails: what it did is read from its output.
out = run(compose + ["build"], env=compose_env, what="podman-compose build (from the cache)", quiet=True)
for name in built:
    check("Successfully tagged localhost/%s:latest" % name in out,
          "podman-compose build built %s:\n%s" % (name, out[-4000:]))
for name, image_id in built.items():
    now = json.loads(run(["podman", "image", "inspect", "localhost/%s:latest" % name], env=env,
                         quiet=True))[0]["Id"]
    check(now == image_id, "podman-compose build made %s anew (%s, the script's %s): the compose "
          "file's build section differs from scripts/container-images.sh" % (name, now, image_id))

# --- up: the server and two workers ------------------------------------------------------------
compose_up = True
run(compose + ["up", "-d"], env=compose_env, what="podman-compose up -d", quiet=True)


class Api(Env):
    """Env's HTTP helpers (request, submit, wait_for, ...) against the server in its container;
    the processes and the folder are podman's, not Env's."""

    def __init__(self, url):  # noqa: super().__init__ would make a folder of its own
        self.url = url

    def log(self, name):
        p = subprocess.run(compose + ["logs"], env=compose_env, capture_output=True, text=True, cwd=workdir)
        return (p.stdout + p.stderr)[-6000:]


api = Api("http://127.0.0.1:%d" % port)


def container_ids(service):
    out = run(["podman", "ps", "-a", "-q", "--no-trunc",
               "--filter", "label=com.docker.compose.project=%s" % project,
               "--filter", "label=com.docker.compose.service=%s" % service], env=env, quiet=True)
    return out.split()


def container_log(cid):
    p = subprocess.run(["podman", "logs", "--tail", "40", cid], env=env, text=True,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    return p.stdout


def health():
    try:
        with urllib.request.urlopen(api.url + "/api/v1/health", timeout=5) as r:
            return json.loads(r.read())
    except OSError:
        return None


t = time.time()
h = api.wait_for(health, 90, "the server's /api/v1/health on port %d" % port)
times.append(("server answers", time.time() - t))
check(h.get("source_revision") == revision,
      "/api/v1/health reports source revision %s, HEAD is %s" % (h.get("source_revision"), revision))
workers = container_ids("worker")
check(len(container_ids("server")) == 1 and len(workers) == 2,
      "one server and two worker containers: %s, %s" % (container_ids("server"), workers))
for cid in container_ids("server") + workers:
    state = run(["podman", "inspect", "--format", "{{.State.Status}}", cid], env=env, quiet=True).strip()
    check(state == "running", "container %s is running: %s\n%s" % (
        cid[:12], state, container_log(cid)))
names = {}
for cid in workers:
    hostname = run(["podman", "inspect", "--format", "{{.Config.Hostname}}", cid], env=env, quiet=True)
    names[cid] = hostname.strip() + ":1"  # the worker's default name: host name and pid (1)


def both_workers_seen():
    metrics = api.get_bytes("/metrics")[1].decode()
    return all('compaction_worker_last_seen_timestamp_seconds{worker="%s"}' % n in metrics
               for n in names.values())


api.wait_for(both_workers_seen, 60, "both workers (%s) to ask the server for work" % sorted(names.values()))

# --- a sweep at the fast preset -----------------------------------------------------------------
t = time.time()
points = [{"S": S, "R": 1e-3, "phi": 0.4} for S in (0.1, 0.2, 0.4)]
sweep = api.submit({"name": "container", "points": points, "numerics": {"preset": "fast"}}, SUBMIT_TOKEN)
check(sweep["created"]["new"] == 3, "3 new jobs: %s" % sweep)
done = api.wait_sweep_done(sweep["id"], 600)
times.append(("the sweep (3 jobs, fast preset)", time.time() - t))
check(done["counts"]["succeeded"] == 3, "every job succeeded: %s" % done["counts"])
jobs = api.get("/api/v1/jobs?sweep=%d" % sweep["id"])["jobs"]
ran_on = set()
for job in jobs:
    detail = api.get("/api/v1/jobs/%d" % job["id"])
    r = detail["result"]
    check(r is not None and r["source_revision"] == revision,
          "job %d's result names revision %s: %s" % (job["id"], revision, r and r["source_revision"]))
    check(r["worker"] in names.values(), "job %d ran on one of the two workers: %s" % (job["id"], r["worker"]))
    ran_on.add(r["worker"])
    status, npy = api.get_bytes("/api/v1/jobs/%d/artifacts/spacetime.npy" % job["id"])
    check(status == 200 and npy.startswith(b"\x93NUMPY"), "job %d's spacetime.npy downloads" % job["id"])
print("sweep %d: 3 jobs succeeded on %d of the 2 workers" % (sweep["id"], len(ran_on)))

# --- stop (SIGTERM), every container exits 0; down ----------------------------------------------
run(compose + ["stop", "-t", "30"], env=compose_env, what="podman-compose stop", quiet=True)
for cid in container_ids("server") + workers:
    state = run(["podman", "inspect", "--format", "{{.State.Status}} {{.State.ExitCode}}", cid],
                env=env, quiet=True).split()
    check(state == ["exited", "0"], "container %s exits 0 on SIGTERM: %s\n%s" % (
        cid[:12], state, container_log(cid)))
run(compose + ["down", "-v"], env=compose_env, what="podman-compose down -v", quiet=True)
compose_up = False
check(container_ids("server") + container_ids("worker") == [], "down removes the containers")
volumes = run(["podman", "volume", "ls", "-q", "--filter", "label=com.docker.compose.project=%s" % project],
              env=env, quiet=True).split()
check(volumes == [], "down -v removes the data volume: %s" % volumes)
# podman-compose 1.0.3's down leaves the project's network: removed here (its bridge goes with it).
run(["podman", "network", "rm", project + "_default"], env=env, quiet=True)

for name in ("debian", "compaction-server", "compaction-worker"):
    print("image localhost/%s: %.0f MB" % (name, images[name]["Size"] / 1e6))
for step, secs in times:
    print("%-45s %6.1f s" % (step, secs))
print("ok in %.0f s" % (time.time() - T0))
