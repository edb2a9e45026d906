"""End to end: the Python client (python/), installed with pip into a venv in a temporary folder
(offline: no index, the interpreter's own setuptools, Debian's wheel of `wheel` when the venv
lacks it), drives a real server with tokens and one real worker. It submits a tiny grid at the
fastest preset, waits with the progress bar, and reads the results, the phase map, the
artifacts and the space-time map, each with and without pandas and numpy as far as this
interpreter has them; a timeout, a cancel, a points sweep that reuses the grid's results, and
bad requests that raise ApiError with the server's own status, field and message.

The script runs twice: first with the interpreter ctest gives it, which makes the venv and
installs the package, then with the venv's interpreter (COMPACTION_E2E_CLIENT_VENV set), which
runs the checks, so that the package is imported from the venv and not from the source tree."""
import contextlib
import io
import json
import math
import os
import shutil
import signal
import struct
import subprocess
import sys
import tempfile

from e2e_lib import Env, bin_dir_from_args, check, fail, stop

HERE = os.path.dirname(os.path.abspath(__file__))
PACKAGE_DIR = os.path.join(HERE, "..", "..", "python")
# Debian's wheels of pip, setuptools and wheel (python3-pip-whl, python3-setuptools-whl,
# python3-wheel-whl): what an offline venv can install its build tools from.
DEBIAN_WHEELS = "/usr/share/python-wheels"
STAGE_VARIABLE = "COMPACTION_E2E_CLIENT_VENV"


def run(command, what):
    p = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, PIP_DISABLE_PIP_VERSION_CHECK="1"))
    check(p.returncode == 0, "%s failed (%s):\n%s" % (what, " ".join(command), p.stdout[-4000:]))


def install_in_venv(folder):
    """Copies the package (pip builds in the source folder) and pip-installs it into a new venv;
    returns the venv's interpreter."""
    source = os.path.join(folder, "python")
    shutil.copytree(PACKAGE_DIR, source,
                    ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"))
    venv = os.path.join(folder, "venv")
    # The system's site packages stay visible: pandas and numpy are used where installed.
    run([sys.executable, "-m", "venv", "--system-site-packages", venv], "python3 -m venv")
    python = os.path.join(venv, "bin", "python")
    missing = [m for m in ("setuptools", "wheel")
               if subprocess.run([python, "-c", "import " + m]).returncode != 0]
    if missing:
        check(os.path.isdir(DEBIAN_WHEELS),
              "the venv lacks %s and %s is missing (scripts/install-deps.sh installs it)"
              % (" and ".join(missing), DEBIAN_WHEELS))
        run([python, "-m", "pip", "install", "--no-index", "--no-cache-dir", "--find-links",
             DEBIAN_WHEELS, *missing], "installing " + " and ".join(missing))
    run([python, "-m", "pip", "install", "--no-index", "--no-cache-dir", "--no-build-isolation",
         source], "pip install of python/")
    return python


if not os.environ.get(STAGE_VARIABLE):
    bin_dir = bin_dir_from_args()
    folder = tempfile.mkdtemp(prefix="compaction-e2e-python-venv-")
    try:
        python = install_in_venv(folder)
        code = subprocess.run([python, os.path.abspath(__file__), bin_dir],
                              env=dict(os.environ, **{STAGE_VARIABLE: "1"})).returncode
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    sys.exit(code)

# --- in the venv ---
import compaction_client  # noqa: E402
from compaction_client import RESULT_COLUMNS, ApiError, Client, NpyError, log_axis  # noqa: E402


def importable(name):
    try:
        __import__(name)
        return True
    except ImportError:
        return False


def raises(call, kind):
    try:
        call()
    except kind as e:
        return e
    fail("%s was not raised" % kind.__name__)


check(os.path.abspath(compaction_client.__file__).startswith(os.path.abspath(sys.prefix)),
      "the package is imported from the venv: %s" % compaction_client.__file__)
has_pandas, has_numpy = importable("pandas"), importable("numpy")
print("pandas %s, numpy %s" % ("installed" if has_pandas else "absent",
                               "installed" if has_numpy else "absent"))

SUBMIT, WORKER = "submit-secret", "worker-secret"
TINY = {"eps_end": 0.03}  # at the fast preset: a second or so per job
env = Env(bin_dir_from_args(), "python-client")
env.start_server("--submit-token", SUBMIT, "--worker-token", WORKER)
os.environ.pop("COMPACTION_SUBMIT_TOKEN", None)
client = Client(env.url, token=SUBMIT)

check(Client(env.url + "/api/v1/").health()["engine_version"] == env.get("/api/v1/health")["engine_version"],
      "a url ending in /api/v1/ names the same server")
check("fast" in [p["name"] for p in client.presets()["presets"]], "the presets")
check(client.limits()["scene"]["phi"]["lo"] == 0.2, "the limits")

# --- errors carry the server's status, field and message ---
grid = {"name": "bad", "S": 1e-2, "R": 1e-3, "phi": 0.9, "numerics": {"preset": "fast"}}
status, said = env.request("POST", "/api/v1/sweeps", grid, token=SUBMIT)
e = raises(lambda: client.submit_grid("bad", 1e-2, 1e-3, 0.9, preset="fast"), ApiError)
check(status == 422 and e.status == 422 and e.field == "phi" == said["error"]["field"]
      and e.message == said["error"]["message"] and "[0.2, 0.8]" in e.message,
      "phi = 0.9: %r against the server's %s" % (e, said))
check(str(e) == "POST /api/v1/sweeps: 422 phi: " + said["error"]["message"], "str: %s" % e)
e = raises(lambda: Client(env.url).submit_grid("t", 1e-2, 1e-3, 0.4), ApiError)
check(e.status == 401 and e.field == "Authorization" and "Bearer token is required" in e.message,
      "no token: %r" % e)
e = raises(lambda: Client(env.url, token="wrong").submit_grid("t", 1e-2, 1e-3, 0.4), ApiError)
check(e.status == 403 and e.message == "wrong token", "a wrong token: %r" % e)
e = raises(lambda: client.submit_grid("t", 1e-2, 1e-3, 0.4, preset="quick"), ApiError)
check(e.status == 422 and e.field == "numerics.preset" and "fast" in e.message, "preset: %r" % e)
e = raises(lambda: client.submit_points("t", [{"S": 1e-2, "R": 1e-3, "phi": 0.9},
                                              {"S": 1e-2, "R": 1e-3}]), ApiError)
check(e.status == 422 and e.field == "points[0].phi", "the first bad point is named: %r" % e)
e = raises(lambda: client.sweep(999999), ApiError)
check(e.status == 404 and e.message == "no such sweep", "unknown sweep: %r" % e)
e = raises(lambda: client.submit_points("t", [(1e-2, 1e-3)]), ValueError)
check("points[0]" in str(e) and "2 values" in str(e), "a point of two values: %s" % e)
check(client.sweeps() == [], "refused requests created nothing")

# --- no worker yet: a wait times out, a cancel ends the sweep ---
lone = client.submit_grid("lone", 0.2, 1e-2, 0.4, preset="fast", numerics=TINY)
e = raises(lambda: client.wait(lone, progress=False, timeout=0), TimeoutError)
check("1 queued" in str(e), "the timeout says what is left: %s" % e)
check(client.cancel(lone) == {"id": lone["id"], "cancelled_jobs": 1}, "cancel")
check(client.wait(lone, progress=False)["state"] == "cancelled", "a cancelled sweep ends a wait")

# --- a tiny grid at the fastest preset, run by one real worker ---
sweep = client.submit_grid("tiny", log_axis(0.05, 0.1, 2), [1e-3], 0.4, preset="fast",
                           numerics=TINY, priority=5)
check(sweep["created"]["new"] == 2 and sweep["created"]["preset"] == "fast", "created: %s" % sweep)
worker = env.start_worker("w1", "--token", WORKER)
bar = io.StringIO()
with contextlib.redirect_stderr(bar):
    done = client.wait(sweep["id"], timeout=120, poll=0.2)
check(done["state"] == "done" and done["counts"]["succeeded"] == 2, "done: %s" % done["counts"])
last = bar.getvalue().split("\r")[-1]
check(last.startswith("sweep %d [%s]" % (sweep["id"], "#" * 30)) and " 2/2 done, 0 failed, 0:"
      in last and last.endswith("\n"), "the progress bar's last line: %r" % last)

rows = client.results(sweep, frame=False)
check(sorted(r["S"] for r in rows) == [0.05, 0.1] and all(r["R"] == 1e-3 for r in rows),
      "a row per point: %s" % rows)
for r in rows:
    check(r["state"] == "succeeded" and r["status"] in ("ok", "unstable")
          and r["source_revision"] and r["engine_version"] and r["cells_per_unit"] == 8
          and r["eps_end"] == 0.03, "row of job %d: %s" % (r["job_id"], r))
    check(set(RESULT_COLUMNS) <= set(r) and "scene" not in r, "columns of job %d" % r["job_id"])
if has_pandas:
    frame = client.results(sweep)
    check(type(frame).__name__ == "DataFrame" and list(frame.columns) == list(rows[0])
          and sorted(frame["job_id"]) == sorted(r["job_id"] for r in rows),
          "results as a DataFrame:\n%s" % frame)
else:
    e = raises(lambda: client.results(sweep), ImportError)
    check("python3-pandas" in str(e) and "frame=False" in str(e),
          "results() without pandas raises, naming Debian's package, and returns no list: %s" % e)

points = client.phase_map(0.4, sweep=sweep, frame=False)
check(sorted(p["job_id"] for p in points) == sorted(r["job_id"] for r in rows)
      and all(p["state"] == "succeeded" for p in points), "the phase map: %s" % points)
check(len(client.phase_map(0.4, frame=False)) == 3, "the phase map of all sweeps (the cancelled job too)")
check(client.phase_map(0.5, frame=False) == [], "nothing at phi = 0.5")
if has_pandas:
    check(len(client.phase_map(0.4, sweep=sweep)) == 2, "the phase map as a DataFrame")
else:
    e = raises(lambda: client.phase_map(0.4, sweep=sweep), ImportError)
    check("python3-pandas" in str(e), "phase_map() without pandas raises: %s" % e)

# --- artifacts and the space-time map ---
job_id = rows[0]["job_id"]
listed = {a["name"]: a for a in client.artifacts(job_id)}
for name in ("summary.json", "frames.csv", "spacetime.npy", "spacetime.png", "velocity.npy"):
    check(name in listed, "artifact %s (have %s)" % (name, sorted(listed)))
data = client.artifact(job_id, "spacetime.npy")
check(len(data) == listed["spacetime.npy"]["size"], "the size listed is the size downloaded")
folder = os.path.join(env.dir, "bundle")
os.makedirs(folder)
path = client.download(job_id, "spacetime.npy", folder)
with open(path, "rb") as f:
    check(f.read() == data, "download writes the artifact's bytes")
written = client.download_bundle(job_id, os.path.join(folder, "all"))
check(sorted(os.path.basename(p) for p in written) == sorted(listed)
      and all(os.path.getsize(p) == listed[os.path.basename(p)]["size"] for p in written),
      "download_bundle writes every artifact")
e = raises(lambda: client.artifact(job_id, "nothing.npy"), ApiError)
check(e.status == 404 and e.field == "name", "an unknown artifact: %r" % e)

summary = client.job(job_id)["result"]["summary"]
n_frames, n_rows = summary["spacetime"]["shape"]
lists = client.spacetime(job_id, array=False)
check(len(lists) == n_frames and all(len(row) == n_rows for row in lists),
      "the space-time map is [%d, %d] as summary.json says" % (n_frames, n_rows))
flat = [v for row in lists for v in row]
# The data of a format 1.0 file start after the 10 bytes of magic, version and length and the
# header: read here with struct, apart from the client's reader.
offset = 10 + struct.unpack_from("<H", data, 8)[0]
check(flat == list(struct.unpack_from("<%df" % len(flat), data, offset))
      and all(math.isfinite(v) and v >= 0 for v in flat),
      "the values are the file's float32 rates")
velocity = client.load_npy(job_id, "velocity.npy", array=False)
check([len(velocity), len(velocity[0])] == summary["velocity"]["shape"], "velocity.npy's shape")
if has_numpy:
    import numpy
    grid_map = client.spacetime(job_id)
    check(isinstance(grid_map, numpy.ndarray) and grid_map.shape == (n_frames, n_rows)
          and grid_map.dtype == numpy.float32 and grid_map.tolist() == lists,
          "the space-time map as a numpy array equals the lists")
else:
    e = raises(lambda: client.spacetime(job_id), ImportError)
    check("python3-numpy" in str(e) and "array=False" in str(e),
          "spacetime() without numpy raises, naming Debian's package: %s" % e)
e = raises(lambda: client.load_npy(job_id, "summary.json"), NpyError)
check("not a .npy file" in str(e), "a file that is not .npy: %s" % e)

# --- explicit points: both were computed by the grid, so nothing runs again ---
again = client.submit_points("again", [(0.05, 1e-3, 0.4), {"S": 0.1, "R": 1e-3, "phi": 0.4}],
                             preset="fast", numerics=TINY)
check(again["created"]["reused"] == 2 and again["created"]["new"] == 0, "reuse: %s" % again)
check(client.wait(again, progress=False)["counts"]["succeeded"] == 2, "the points sweep is done")
check(sorted(s["id"] for s in client.sweeps()) == sorted([lone["id"], sweep["id"], again["id"]]),
      "every sweep is listed")
check(len(client.jobs(sweep=sweep)) == 2 and len(client.jobs(state="cancelled")) == 1
      and len(client.jobs(phi=0.4)) == 3, "jobs by sweep, state and phi")

# --- the run table: every job as columns, filtered, sorted, its pages read by their cursor ---
table = client.runs(frame=False)
check([r["id"] for r in table] == sorted(j["id"] for j in client.jobs()),
      "the run table holds every job: %s" % table)
check([r["id"] for r in client.runs(sweep=sweep, frame=False)]
      == sorted(j["id"] for j in client.jobs(sweep=sweep)), "the runs of a sweep")
check([r["state"] for r in client.runs(state=["cancelled", "failed"], frame=False)] == ["cancelled"],
      "a list is comma-separated")
check(all(r["preset"] == "fast" for r in table), "every run made from the fast preset: %s" % table)
by_S = client.runs(sort="-S", frame=False)
check([r["S"] for r in by_S] == sorted((r["S"] for r in table), reverse=True), "sorted by -S")
check([r["id"] for r in client.runs(S=(0.06, None), frame=False)]
      == [r["id"] for r in table if r["S"] >= 0.06], "a range with an open end")
check(len(client.runs(limit=2, frame=False)) == 2, "at most limit rows")
compaction_client.client.PAGE_LIMIT = 1  # every row a page of its own: the cursor walks them
check(client.runs(sort="-S", frame=False) == by_S, "pages of one row read by their cursor")
compaction_client.client.PAGE_LIMIT = 1000
e = raises(lambda: client.runs(colour="red"), ApiError)
check(e.status == 422 and e.field == "colour", "an unknown filter: %r" % e)
e = raises(lambda: client.runs(cls="g"), ApiError)
check(e.status == 422 and e.field == "class", "cls is the class filter: %r" % e)
if has_pandas:
    frame = client.runs(sort="-S")
    check(list(frame.columns) == client.limits()["jobs"]["columns"] and len(frame) == len(table),
          "runs as a DataFrame:\n%s" % frame)

# --- replicates: one point run three times, read together as the map's point ---
e = raises(lambda: client.submit_points("reps", [(0.1, 1e-3, 0.4)], preset="fast", numerics=TINY,
                                        replicates=(0, 0.01)), ApiError)
check(e.status == 422 and e.field == "replicates.n", "n = 0: %r" % e)
e = raises(lambda: client.submit_points("reps", [(0.1, 1e-3, 0.4)], preset="fast", numerics=TINY,
                                        replicates=3), ApiError)
check(e.status == 422 and e.field == "replicates.perturbation",
      "replicates of an unperturbed regular lattice: %r" % e)
reps = client.submit_points("reps", [(0.1, 1e-3, 0.4)], preset="fast", numerics=TINY,
                            replicates=(3, 0.01))
check(reps["created"]["new"] == 3, "three replicates: %s" % reps["created"])
check(client.wait(reps, progress=False, timeout=120)["counts"]["succeeded"] == 3, "replicates done")
same = client.submit_points("same", [(0.1, 1e-3, 0.4)], preset="fast",
                            numerics=dict(TINY, seeds=[1, 2, 3], perturbation=0.01))
check(same["created"]["reused"] == 3, "numerics.seeds names the same runs: %s" % same["created"])
runs = client.phase_map(0.4, sweep=reps, frame=False)
pts = client.points(0.4, sweep=reps, frame=False)
check(len(runs) == 3 and len(pts) == 1 and len({r["point_id"] for r in runs}) == 1
      and pts[0]["point_id"] == runs[0]["point_id"], "three runs, one point: %s" % pts)
pt = pts[0]
# At eps 0.03 a run may end before the classifier can read it (no class): the point reads the
# labelled ones, and without any it has no label.
labels = [r["class"] for r in runs if r["class"] is not None]
top = max((labels.count(c) for c in labels), default=0)
tied = {c for c in labels if labels.count(c) == top}  # a tie goes by confidence (docs/replicates.md)
majority = pt["label"]
check(pt["runs"] == pt["finished"] == 3 and pt["labelled"] == len(labels)
      and (majority in tied if labels else majority is None)
      and (pt["share"] is None if not labels else abs(pt["share"] - top / len(labels)) < 1e-12)
      and pt["robust"] == (top == 3)
      and abs(sum(pt["p_" + c] for c in "abcdef") - (1 if labels else 0)) < 1e-12
      and sorted(pt["jobs"]) == sorted(r["job_id"] for r in runs),
      "the point reads its runs' labels %s: %s" % (labels, pt))
speeds = [r["band_speed_ratio"] for r in runs
          if majority and r["class"] == majority and r["band_speed_ratio"] is not None]
check(pt["band_speed_ratio_n"] == len(speeds)
      and (not speeds or abs(pt["band_speed_ratio_mean"] - sum(speeds) / len(speeds)) < 1e-12),
      "c_b/V over the majority's runs: %s against %s" % (pt, speeds))
check(client.points(sweep=reps, frame=False) == pts, "a sweep's points from its export")
siblings = client.job(runs[0]["job_id"])["replicates"]
check(sorted(siblings) == sorted(r["job_id"] for r in runs if r["job_id"] != runs[0]["job_id"]),
      "a run names its replicates: %s" % siblings)
if has_pandas:
    frame = client.points(0.4, sweep=reps)
    check(list(frame.columns) == compaction_client.POINT_COLUMNS and len(frame) == 1,
          "points as a DataFrame:\n%s" % frame)

# --- an adaptive sweep: it grows by itself within its budget and wait() sees it end ---
e = raises(lambda: client.submit_adaptive("map", 0.4, (0.02, 0.1), (1e-4, 1e-1), initial=(2, 2),
                                          resolution_decades=0.25, budget=3), ApiError)
check(e.status == 422 and e.field == "adaptive.budget", "a budget below the grid: %r" % e)
grown = client.submit_adaptive("map", 0.4, (0.02, 0.1), (1e-4, 1e-1), initial=(2, 2),
                               resolution_decades=0.25, budget=6, in_flight=2, preset="fast",
                               numerics=TINY)
check(grown["counts"]["total"] == 4 and grown["request"]["adaptive"]["budget"] == 6,
      "the initial 2 x 2 grid: %s" % grown["counts"])
finished = client.wait(grown, progress=False, timeout=120)
check(4 <= finished["counts"]["total"] <= 6 and finished["state"] == "done",
      "the adaptive sweep ended within its budget: %s" % finished["counts"])
plan = client.plan(grown)
check(plan["state"] in ("resolved", "budget_spent", "unresolved")
      and plan["runs"]["done"] == finished["counts"]["total"],
      "wait() returns once the plan has ended, not in the moment before points are added: %s" % plan)
e = raises(lambda: client.plan(sweep), ApiError)
check(e.status == 409 and e.field == "id", "a grid sweep has no plan: %r" % e)

# --- the map's regions, and the export file with and without the runs' files ---
regions = client.regions(0.4, sweep=grown, grid=8)
check(regions["grid"] == 8 and len(regions["classes"]) == 8 and len(regions["uncertainty"]) == 8
      and regions["runs"] >= 1, "the regions the adaptive sweep's runs predict: %s" % regions)
e = raises(lambda: client.regions(0.95), ApiError)
check(e.status == 422 and e.field == "phi", "regions refuse phi = 0.95: %r" % e)
full = client.export_archive(grown, os.path.join(env.dir, "full.export.json"))
bare = client.export_archive(grown, os.path.join(env.dir, "bare.export.json"), artifacts="none")
with open(full) as f_full, open(bare) as f_bare:
    full_doc, bare_doc = json.load(f_full), json.load(f_bare)
check(len(bare_doc["runs"]) == len(full_doc["runs"]) >= 1
      and all(r["artifacts"] == [] for r in bare_doc["runs"])
      and any(r["artifacts"] for r in full_doc["runs"])
      and os.path.getsize(bare) < os.path.getsize(full), "an export without the runs' files")

check(stop(worker, signal.SIGTERM) == 0, "the worker exits 0 on SIGTERM")
check(stop(env.server, signal.SIGTERM) == 0, "the server exits 0 on SIGTERM")
print("ok")
