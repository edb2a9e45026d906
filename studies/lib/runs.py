"""Running compaction-run scenes for the study scripts, cached and in parallel.

A scene is a name plus the runner's flags. Its bundle goes to WORK/name; a bundle that exists
(summary.json written, which the runner does last) is not computed again, so an interrupted
script resumes where it stopped. Scenes run as separate processes, `jobs` at a time, each on
one thread, so wall times stay comparable with one another.
"""
import concurrent.futures
import csv
import json
import os
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
RUN = os.path.join(ROOT, "build", "bin", "compaction-run")
CLASSIFY = os.path.join(ROOT, "build", "bin", "compaction-classify")


def scene_key(key):
    """A scene key's entry in schema/scene.schema.json (its default and range), which
    scene_schema_gtest keeps equal to the engine's SceneParams and limits."""
    with open(os.path.join(ROOT, "schema", "scene.schema.json")) as f:
        return json.load(f)["properties"][key]


def check_cells_per_strut(ap, value):
    """Exits through the parser when --cells-per-strut is outside the engine's range."""
    cps = scene_key("cells_per_strut")
    if not cps["minimum"] <= value <= cps["maximum"]:
        ap.error("--cells-per-strut: %g is outside %g-%g" % (value, cps["minimum"], cps["maximum"]))


def write_report(path, lines, echo=True):
    """Writes a study's Markdown report (its lines, a newline at the end) to `path`, making its
    folder, and prints it unless `echo` is false."""
    text = "\n".join(lines) + "\n"
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    if echo:
        print(text, end="", flush=True)


def flag_args(flags):
    """A scene's flags as the runner's command-line arguments."""
    return [arg for k, v in flags.items() for arg in ("--" + k.replace("_", "-"), str(v))]


def command(out, flags, run=RUN):
    return [run, "--progress", "none", "--threads", "1", "--out", out] + flag_args(flags)


def finished(out):
    """A bundle that a run completed (ok or unstable); a cancelled run's bundle does not count."""
    try:
        return summary(out)["status"] != "cancelled"
    except (OSError, ValueError, KeyError):
        return False


def run_one(work, name, flags, run=RUN):
    """Runs one scene unless its bundle exists; returns the bundle directory."""
    out = os.path.join(work, name)
    if not finished(out):
        cmd = command(out, flags, run)
        print("run", " ".join(cmd[1:]), file=sys.stderr, flush=True)
        subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    return out


def refused(flags, run=RUN):
    """The runner's reason when it refuses the scene (`--check`, its validate()), else None."""
    res = subprocess.run([run, "--check"] + flag_args(flags), capture_output=True, text=True)
    return None if res.returncode == 0 else (res.stderr.strip().splitlines() or ["refused"])[-1]


def check_all(scenes, run=RUN):
    """Asks the runner to validate every scene before any runs: a flag out of range exits naming
    the scene and the runner's own message, not an hour later."""
    for name, flags in scenes.items():
        reason = refused(flags, run)
        if reason is not None:
            sys.exit("%s: %s" % (name, reason))


def run_all(work, scenes, jobs=1, run=RUN):
    """scenes: {name: flags}. Runs the missing ones, `jobs` at a time; returns {name: dir}."""
    os.makedirs(work, exist_ok=True)
    # The most expensive first (steps ~ cells^3 / S per unit strain), so the last to finish
    # is a cheap one and the lanes stay busy.
    default_cells = scene_key("cells_per_strut")["default"]
    def cost(item):
        f = item[1]
        phi = float(f.get("phi", 0.4))
        c = float(f.get("cells_per_unit") or
                  float(f.get("cells_per_strut", default_cells)) / (1 - (1 - min(phi, 0.99)) ** 0.5))
        n = 17 if f.get("geometry") == "full2d" else 1
        return -(c ** 3) * n * float(f.get("eps_end", 0.6)) / float(f["S"])

    todo = sorted(scenes.items(), key=cost)
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, jobs)) as pool:
        futures = {name: pool.submit(run_one, work, name, flags, run) for name, flags in todo}
        return {name: f.result() for name, f in futures.items()}


def summary(out):
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def frames(out):
    """frames.csv as a dict of float columns."""
    with open(os.path.join(out, "frames.csv")) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def classify(out, classify_bin=CLASSIFY):
    """The classifier's JSON for a bundle (recomputed: the classifier may be newer than the run)."""
    res = subprocess.run([classify_bin, "--compact", out], check=True, capture_output=True, text=True)
    return json.loads(res.stdout)


def reading(out, classify_bin=CLASSIFY):
    """What the studies report of one bundle: the classifier's label, confidence, N_r and both
    readings of c_b/V with their uncertainty (docs/classifier.md), the wall time and status,
    and the summary and features whole for a study's own columns; None when the bundle is not
    finished."""
    if not finished(out):
        return None
    s = summary(out)
    c = classify(out, classify_bin)
    f = c.get("features") or {}
    return dict(band_speeds(f), label=c.get("class") or "none", confidence=c.get("confidence"),
                n_r=c.get("n_reflections"), wall=s["wall_seconds"], status=s["status"],
                summary=s, features=f)


def band_speeds(features):
    """The readings of c_b/V with their uncertainties (docs/classifier.md) from a
    classification's features: fit, fit_err, transit, transit_err, and the early stage's in the
    velocity map, early, early_err (the band's middle) and lead, lead_err (its leading edge);
    None where absent."""
    f = features or {}
    return {"fit": f.get("band_speed_ratio"), "fit_err": f.get("band_speed_error"),
            "transit": f.get("band_speed_transit"),
            "transit_err": f.get("band_speed_transit_error"),
            "early": f.get("band_speed_early"), "early_err": f.get("band_speed_early_error"),
            "lead": f.get("band_speed_lead"), "lead_err": f.get("band_speed_lead_error")}
