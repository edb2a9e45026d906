"""Where the two bands of each two-sided run start and meet: what the classifier's class (c)
rests on, read from the runs' bundles.

The classifier calls a run two-sided (`two_sided`, the one feature that makes (c)) when a front
from the bottom plate starts while the top band is on its first leg; since 0988e4f it must also
start before the top band has passed the middle of the sample (engine/classify, features.cpp),
and runs stored before then were two-sided by the first condition alone. The paper's (c) is
"crossing bands emerging from the two ends"; its example has the bottom band start at
eps ~ 0.05 and the two meet at mid-height. This lists, for every run
of the given sweeps whose stored features say two-sided and whose bundle is on this machine,
the bottom front that made it so: when it starts, how far it travels, and when the top band
passes mid-height, so a reader sees which (c) are bands emerging from both ends and which are a
few bottom rows yielding as the top band arrives.

usage: PYTHONPATH=python python3 -m studies.phase_map.crossing --server URL --sweep ID
       [--sweep ID ...] --artifacts DIR [...] [--classify build/bin/compaction-classify]
       [--out FILE]

DIR holds bundles named job-ID-*: the server's artifact directory (`--db X` keeps them in
X.artifacts/), or runs made again with compaction-run from a job's scene (GET /jobs/ID).
"""
import argparse
import glob
import json
import os
import subprocess
import sys

from compaction_client import Client
from studies.lib.cells import fmt
from studies.phase_map.fig2 import ROOT, job_of
from studies.phase_map.redecide import classifier_revision


def classify_fronts(classify, bundle):
    """compaction-classify's verdict on the bundle with its fronts."""
    out = subprocess.run([classify, "--fronts", "--compact", bundle], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


def crossing(fr):
    """The top band from the onset and the bottom front that made a stored run two-sided (the
    condition before 0988e4f; whether today's classifier agrees is its own `two_sided`), the
    bottom front starting first; None if there is none. Whether a front starts at the onset and
    where its first leg ends are the classifier's own readings (compaction-classify --fronts)."""
    pairs = [(a, b) for a in fr if a["origin"] == "top" and a["at_onset"]
             for b in fr if b["origin"] == "bottom"
             and b["start_eps"] < a["first_leg_end_eps"] and a["start_eps"] < b["first_leg_end_eps"]]
    return min(pairs, key=lambda p: p[1]["start_eps"]) if pairs else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--server", required=True, help="the server's URL")
    ap.add_argument("--sweep", type=int, action="append", required=True, help="a sweep's id")
    ap.add_argument("--artifacts", action="append", required=True,
                    help="a directory of bundles job-ID-* (repeatable)")
    ap.add_argument("--classify", default=os.path.join(ROOT, "build", "bin", "compaction-classify"))
    ap.add_argument("--out", help="write the table here (markdown) instead of stdout")
    a = ap.parse_args()
    for d in a.artifacts:
        if not os.path.isdir(d):
            sys.exit("crossing.py: no directory %s" % d)
    client = Client(a.server)
    seen, rows, missing = set(), [], []
    for sweep in a.sweep:
        for r in client.results(sweep, frame=False):
            if r["job_id"] in seen or r["state"] != "succeeded":
                continue
            seen.add(r["job_id"])
            if not (r.get("features") or {}).get("two_sided"):
                continue
            j = job_of(r)
            bundle = [b for d in a.artifacts
                      for b in sorted(glob.glob(os.path.join(d, "job-%d-*" % j["id"])))]
            if not bundle:
                missing.append(j)
                continue
            today = classify_fronts(a.classify, bundle[0])
            rows.append((j, crossing(today["fronts"]), today, r["confidence"]))
    lines = ["<!-- written by python3 -m studies.phase_map.crossing --sweep %s; do not edit -->"
             % " --sweep ".join(map(str, a.sweep)), "",
             "| job | S | R | stored label | bottom front starts at eps | travels from / to "
             "height | top band passes mid-height (else ends its first leg) at eps | two-sided today | "
             "today's label |",
             "|---|---|---|---|---|---|---|---|---|"]
    still = 0
    for j, pair, today, confidence in sorted(rows, key=lambda x: (x[0]["S"], x[0]["R"])):
        stored = "%s %s" % (j["classifier"] or "unclassified", fmt(confidence, 2))
        verdict = "%s %s" % (today["class"], fmt(today["confidence"], 2))
        still += bool(today["features"]["two_sided"])
        if pair is None:
            lines.append("| %d | %s | %s | %s | - | - | - | %s | %s |"
                         % (j["id"], fmt(j["S"]), fmt(j["R"]), stored,
                            "yes" if today["features"]["two_sided"] else "no", verdict))
            continue
        top, bottom = pair
        lines.append("| %d | %s | %s | %s | %.3f | %.2f / %.2f | %.3f | %s | %s |"
                     % (j["id"], fmt(j["S"]), fmt(j["R"]), stored, bottom["start_eps"],
                        bottom["start_height"], bottom["end_height"], top["passes_middle_eps"],
                        "yes" if today["features"]["two_sided"] else "no", verdict))
    starts = sorted(p[1]["start_eps"] for _, p, _, _ in rows if p)
    if len(starts) >= 2:  # the widest gap between the bottom fronts' starts splits them in two
        k = max(range(len(starts) - 1), key=lambda i: starts[i + 1] - starts[i])
        lines += ["", "The bottom fronts start at eps %.3f to %.3f (%d runs) or %.3f to %.3f (%d); "
                  "none between." % (starts[0], starts[k], k + 1, starts[k + 1], starts[-1],
                                      len(starts) - k - 1)]
    lines += ["", "Runs stored as two-sided with a bundle here: %d, still two-sided by today's "
              "classifier (%s): %d. Runs stored as two-sided without a bundle here: %s."
              % (len(rows), classifier_revision(a.classify), still,
                 ", ".join("job %d" % j["id"] for j in missing) or "none")]
    text = "\n".join(lines) + "\n"
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
