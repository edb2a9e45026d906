"""Two builds of compaction-classify label stored run bundles alike, byte for byte. A refactoring
that must not change behaviour (issue 48, item 6: "behaviour unchanged, proven") proves with
this that the classifier it touched decides as before: every bundle is classified by both
builds in each mode (indented, --compact, --fronts --compact, --features summary.json), and
their exit status, standard output, standard error and any file they leave behind are compared
byte for byte.

Each run gets a fresh copy of the bundle at the same path, with an empty working directory at
the same path, so a path a classifier prints or a file it writes compares alike; the copy's
files after the run are compared with the bundle's (the classifier reads a bundle and writes
nothing: a file added or changed is listed, and compared between the builds).

--bundles takes bundle directories (holding summary.json) or directories to search for them.
The report says the command, the two builds' --version, every bundle with its scene and the
label both builds gave, and every difference (with the first lines of a diff). Exit status 0
when every output is identical, 1 when any differs.

usage: python3 bench/classify/classify_replay.py --bin build/bin --baseline OLD/build/bin
         --bundles DIR [DIR ...] [--out bench/results/classify_replay.md]
"""
import argparse
import difflib
import hashlib
import json
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

# (name, arguments before the bundle, whether the bundle is given as its summary.json)
MODES = [
    ("indented", [], False),
    ("compact", ["--compact"], False),
    ("fronts", ["--fronts", "--compact"], False),
    ("features", ["--compact", "--features"], True),
]
DIFF_LINES = 40


def find_bundles(roots):
    """Directories holding summary.json, each once, in the order given (sorted under a root)."""
    found, seen = [], set()
    for root in roots:
        root = os.path.abspath(root)
        if not os.path.isdir(root):
            sys.exit("not a directory: %s" % root)
        if os.path.isfile(os.path.join(root, "summary.json")):
            candidates = [root]
        else:
            candidates = sorted(d for d, _, files in os.walk(root) if "summary.json" in files)
        for d in candidates:
            real = os.path.realpath(d)
            if real not in seen:
                seen.add(real)
                found.append(d)
    return found


def tree(d):
    """Relative path -> bytes of every file under d."""
    out = {}
    for base, _, files in os.walk(d):
        for f in files:
            p = os.path.join(base, f)
            with open(p, "rb") as fh:
                out[os.path.relpath(p, d)] = fh.read()
    return out


def classify(binary, bundle, mode, work):
    """Run one classifier on a fresh copy of bundle; its outputs and the files it left."""
    _, args, as_file = mode
    copy, cwd = os.path.join(work, "bundle"), os.path.join(work, "cwd")
    for d in (copy, cwd):
        if os.path.exists(d):
            shutil.rmtree(d)
    shutil.copytree(bundle, copy)
    os.mkdir(cwd)
    before = tree(copy)
    target = os.path.join(copy, "summary.json") if as_file else copy
    p = subprocess.run([os.path.abspath(os.path.join(binary, "compaction-classify"))] + args + [target],
                       cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=300)
    after = tree(copy)
    written = {("bundle/" + k): v for k, v in after.items() if before.get(k) != v}
    written.update({("cwd/" + k): v for k, v in tree(cwd).items()})
    removed = sorted(k for k in before if k not in after)
    return {"rc": p.returncode, "stdout": p.stdout, "stderr": p.stderr, "written": written,
            "removed": removed}


def diff_text(a, b, name):
    lines = list(difflib.unified_diff(a.decode("utf-8", "replace").splitlines(),
                                      b.decode("utf-8", "replace").splitlines(),
                                      "baseline/" + name, "build/" + name, lineterm=""))
    more = len(lines) - DIFF_LINES
    return "\n".join(lines[:DIFF_LINES]) + ("\n... %d more lines" % more if more > 0 else "")


def compare(old, new):
    """Differences between two runs' outputs, as (what, detail) pairs."""
    diffs = []
    if old["rc"] != new["rc"]:
        diffs.append(("exit status", "%d (baseline) against %d (build)" % (old["rc"], new["rc"])))
    for stream in ("stdout", "stderr"):
        if old[stream] != new[stream]:
            diffs.append((stream, diff_text(old[stream], new[stream], stream)))
    for f in sorted(set(old["written"]) | set(new["written"])):
        a, b = old["written"].get(f), new["written"].get(f)
        if a is None or b is None:
            diffs.append(("file " + f, "written by the %s only" % ("build" if a is None else "baseline")))
        elif a != b:
            diffs.append(("file " + f, diff_text(a, b, f)))
    if old["removed"] != new["removed"]:
        diffs.append(("removed files", "%s (baseline) against %s (build)" % (old["removed"], new["removed"])))
    return diffs


def scene(bundle):
    """The few scene keys the report shows, and the label the bundle's run stored."""
    try:
        with open(os.path.join(bundle, "summary.json")) as f:
            s = json.load(f)
    except (OSError, ValueError) as e:
        return "unreadable summary.json (%s)" % e.__class__.__name__, "-"
    p = s.get("params", {})
    preset = (s.get("numerics") or {}).get("preset", "-")
    text = "%s, S %g, R %g, phi %g, %s, eps %g" % (p.get("geometry"), p.get("S"), p.get("R"), p.get("phi"),
                                                  preset, s.get("eps_reached", float("nan")))
    if p.get("structure") == "random":
        text += ", random (seed %s)" % p.get("seed")
    if p.get("transfer") not in (None, "apic"):
        text += ", " + p["transfer"]
    return text, str((s.get("classification") or {}).get("class"))


def label(run):
    try:
        return str(json.loads(run["stdout"]).get("class"))
    except ValueError:
        return "(exit %d)" % run["rc"]


def version(binary):
    p = subprocess.run([os.path.join(binary, "compaction-classify"), "--version"],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    return p.stdout.decode("utf-8", "replace").strip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True, help="directory of the build's compaction-classify")
    ap.add_argument("--baseline", required=True, help="directory of the baseline's compaction-classify")
    ap.add_argument("--bundles", required=True, nargs="+", metavar="DIR",
                    help="bundles (directories with summary.json) or directories to search for them")
    ap.add_argument("--out", default="-", help="the Markdown report (- for stdout) [-]")
    a = ap.parse_args()

    bundles = find_bundles(a.bundles)
    if not bundles:
        sys.exit("no bundle (a directory with summary.json) under %s" % " ".join(a.bundles))
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    rows, problems, compared, output_bytes, touched = [], [], 0, 0, set()
    with tempfile.TemporaryDirectory(prefix="classify-replay-") as work:
        for bundle in bundles:
            labels = {}
            for mode in MODES:
                old = classify(a.baseline, bundle, mode, work)
                new = classify(a.bin, bundle, mode, work)
                compared += 1
                touched.update(f for run in (old, new) for f in list(run["written"]) + run["removed"])
                output_bytes += len(new["stdout"]) + len(new["stderr"])
                if mode[0] == "indented":
                    labels = {"old": label(old), "new": label(new), "rc": new["rc"],
                              "sha": hashlib.sha256(new["stdout"]).hexdigest()[:12]}
                for what, detail in compare(old, new):
                    problems.append((bundle, mode[0], what, detail))
            text, stored = scene(bundle)
            rows.append((bundle, text, stored, labels))

    cmd = "python3 " + " ".join(shlex.quote(x) for x in [os.path.relpath(__file__)] + sys.argv[1:])
    out = ["# Classifier outputs of two builds", "",
           "Made by `%s`, %s." % (cmd, started), "",
           "Baseline: `%s` (`%s`); build: `%s` (`%s`)." % (a.baseline, version(a.baseline), a.bin, version(a.bin)),
           "",
           "%d bundles, each classified in %d modes (%s) by both builds: %d pairs of runs, %d bytes of "
           "output per build. Compared byte for byte: exit status, standard output, standard error and "
           "the files a run leaves in the bundle's copy or its working directory."
           % (len(bundles), len(MODES), ", ".join(m[0] for m in MODES), compared, output_bytes), ""]
    counts = {}
    for _, _, _, l in rows:
        counts[l.get("new")] = counts.get(l.get("new"), 0) + 1
    out += ["Labels the build gave (indented mode): %s." % ", ".join(
        "%s %d" % (k, counts[k]) for k in sorted(counts, key=str)), ""]
    if problems:
        out += ["**%d difference%s** (bundle, mode, what):" % (len(problems), "" if len(problems) == 1 else "s"), ""]
        for bundle, mode, what, detail in problems:
            out += ["- `%s`, %s, %s:" % (bundle, mode, what), "", "```diff", detail, "```", ""]
    else:
        out += ["**Every output identical.**", ""]
    out += ["Files a run wrote, changed or removed: %s." % (", ".join("`%s`" % f for f in sorted(touched))
                                                          if touched else "none, by either build"), ""]
    out += ["| bundle | scene (geometry, S, R, phi, preset, strain reached) | stored label | baseline | build "
            "| exit | stdout sha256 (indented) |",
            "|---|---|---|---|---|---|---|"]
    for bundle, text, stored, l in rows:
        out.append("| `%s` | %s | %s | %s | %s | %s | %s |" % (bundle, text, stored, l.get("old"), l.get("new"),
                                                            l.get("rc"), l.get("sha")))
    out += ["", "Stored label: the one the run wrote into its summary.json, with the classifier of the build "
            "that ran it (None: a run too short to be classified). The bundles are on the machine that made "
            "this report, not in the repository; the scene column says how to make each again with "
            "`compaction-run`.", ""]
    text = "\n".join(out)
    if a.out == "-":
        sys.stdout.write(text)
    else:
        with open(a.out, "w") as f:
            f.write(text)
        print("%d bundles, %d pairs of runs, %d differences; report %s" % (len(bundles), compared, len(problems), a.out))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
