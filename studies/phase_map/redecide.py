"""Decides a sweep's runs again with today's classifier, from each run's bundle or its stored
features.

A run's label is the classifier's verdict when the run finished. When the decision's rules change
(docs/classifier.md), the stored features still hold everything the rules read, so
`compaction-classify --features` gives what today's rules say of each run without running it
again. When the features themselves change (how they are read from the space-time map), only
the run's bundle can say: with --bundles DIR, a run whose bundle is in DIR (job-ID-*, as a
server keeps them in its artifact directory) is decided from it (`compaction-classify DIR`), the
others from their features, and the table says which. This script does that for every finished
run of a sweep and lists where the verdict differs from the stored label.

With --apply BY it records each such verdict as the run's label through the service's human
labels (PUT /jobs/{id}/label, the submit token): the classifier's stored label stays beside it,
the reason names the classifier's revision and its verdict, and the audit keeps who and when
(docs/service.md, "Human labels"). The map, its regions and the planner then read it. A run whose
label is already the verdict is left alone; so is one a person labelled otherwise, unless
--replace-labels.

usage: PYTHONPATH=python python3 -m studies.phase_map.redecide --server URL --sweep ID
       [--bundles DIR ...] [--classifier PATH] [--apply BY]

Prints one line per run whose verdict differs, then a count; exits 1 when the server or the
classifier cannot be used.
"""
import argparse
import glob
import json
import os
import subprocess
import sys

from compaction_client import ApiError, Client
from studies.lib.cells import fmt
from studies.lib.runs import ROOT

# The reason of every label this script sets begins with one of these, so a reader of the audit
# (and a later run of the script) tells them from a person's own.
REASON_PREFIX = {"features": "decided again from the run's stored features by compaction-classify",
                 "bundle": "decided again from the run's bundle by compaction-classify"}


def classifier_revision(classifier):
    """'compaction-classify 0.2.1 (07ea0bca396a)' -> '0.2.1 (07ea0bca396a)'."""
    out = subprocess.run([classifier, "--version"], capture_output=True, text=True, check=True)
    return out.stdout.strip().split(" ", 1)[-1]


def decide(classifier, features=None, bundle=None):
    """Today's verdict on a bundle, else on stored features: compaction-classify's JSON."""
    if bundle:
        out = subprocess.run([classifier, "--compact", bundle], capture_output=True, text=True)
    else:
        out = subprocess.run([classifier, "--compact", "--features", "-"],
                             input=json.dumps({"features": features}), capture_output=True,
                             text=True)
    if out.returncode != 0:
        raise RuntimeError(out.stderr.strip())
    return json.loads(out.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--server", required=True, help="the server's URL, e.g. http://127.0.0.1:8080")
    ap.add_argument("--sweep", type=int, required=True, help="the sweep's id")
    ap.add_argument("--classifier", default=os.path.join(ROOT, "build", "bin", "compaction-classify"),
                    help="compaction-classify to decide with [build/bin/compaction-classify]")
    ap.add_argument("--apply", metavar="BY",
                    help="set each differing verdict as the run's label, by BY (needs the submit "
                         "token: COMPACTION_SUBMIT_TOKEN or --token)")
    ap.add_argument("--token", help="the submit token [env COMPACTION_SUBMIT_TOKEN]")
    ap.add_argument("--bundles", action="append", default=[], metavar="DIR",
                    help="decide a run from its bundle DIR/job-ID-* where there is one (repeatable)")
    ap.add_argument("--replace-labels", action="store_true",
                    help="also replace a label a person set otherwise")
    a = ap.parse_args()
    if a.apply is not None and not a.apply.strip():
        ap.error("--apply: BY must name who applies the verdicts")
    try:
        revision = classifier_revision(a.classifier)
    except (OSError, subprocess.CalledProcessError) as e:
        sys.exit("redecide.py: cannot run the classifier %s: %s" % (a.classifier, e))
    client = Client(a.server, token=a.token)
    try:
        rows = client.results(a.sweep, frame=False)
    except (ApiError, OSError) as e:
        sys.exit("redecide.py: cannot read sweep %d from %s: %s" % (a.sweep, a.server, e))

    for d in a.bundles:
        if not os.path.isdir(d):
            sys.exit("redecide.py: --bundles %s is not a directory" % d)
    decided = differ = applied = 0
    read = {"bundle": 0, "features": 0}
    print("| job | S | R | stored | today | from | confidence | runner-up | person's label | action |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: (r["S"], r["R"])):
        if r["state"] != "succeeded" or not r["features"]:
            continue  # no result, or a run that was not classified (unstable, cancelled)
        bundle = next((b for d in a.bundles
                       for b in sorted(glob.glob(os.path.join(d, "job-%d-*" % r["job_id"])))), None)
        source = "bundle" if bundle else "features"
        try:
            today = decide(a.classifier, r["features"], bundle)
        except (RuntimeError, ValueError) as e:
            sys.exit("redecide.py: job %d: %s" % (r["job_id"], e))
        decided += 1
        read[source] += 1
        verdict = today["class"]
        if verdict == (r["class"] or "unclassified"):
            continue
        differ += 1
        human = r.get("human_label") or {}
        action = "-"
        if a.apply is not None:
            if verdict == "unclassified":
                action = "left: no class to set"
            elif human.get("label") == verdict:
                action = "left: already labelled so"
            elif human and not human.get("reason", "").startswith(tuple(REASON_PREFIX.values())) \
                    and not a.replace_labels:
                action = "left: a person labelled it"
            else:
                reason = ("%s %s (docs/classifier.md): %s with confidence %.2f, runner-up %s; "
                          "the classifier's stored label is %s"
                          % (REASON_PREFIX[source], revision, verdict, today["confidence"],
                             today["runner_up"] or "none", r["class"] or "none"))
                try:
                    client.set_label(r["job_id"], verdict, reason, a.apply)
                except ApiError as e:
                    sys.exit("redecide.py: job %d: %s" % (r["job_id"], e))
                applied += 1
                action = "labelled"
        print("| %d | %s | %s | %s %s | **%s** | %s | %s | %s | %s | %s |"
              % (r["job_id"], fmt(r["S"]), fmt(r["R"]), r["class"] or "-",
                 fmt(r["confidence"], 2), verdict, source, fmt(today["confidence"], 2),
                 today["runner_up"] or "-", human.get("label") or "-", action))
    print("\nredecide.py: sweep %d, %d runs decided again by compaction-classify %s (%d from their "
          "bundle, %d from their stored features): %d differ from their stored label%s"
          % (a.sweep, decided, revision, read["bundle"], read["features"], differ,
             ", %d labelled" % applied if a.apply else ""))


if __name__ == "__main__":
    main()
