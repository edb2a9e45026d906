#!/usr/bin/env bash
# compaction-classify end to end: help, exit 2 for bad usage, a real bundle classified, and its
# stored features (summary.json, as the server stores and exports them) decided again by
# --features to the same JSON, key for key; unreadable features exit 1 naming the problem.
set -u
run="$1"; classify="$2"
source "$(dirname "$0")/../lib/cli_checks.sh"

"$classify" --help > "$out/help" 2>&1; rc=$?
check "help exits 0" test $rc -eq 0
check "help documents --features" grep -q -- "--features FILE" "$out/help"

"$classify" 2> "$out/err"; rc=$?
check "no input exits 2" test $rc -eq 2
check "no input says what to give" grep -q "give either RESULT_DIR or --features FILE" "$out/err"

# An explosive run (class (e)), short and coarse: a fraction of a second.
"$run" --S 0.1 --R 1e-5 --phi 0.4 --cells-per-unit 6 --eps-end 0.1 --out "$out/b" > /dev/null 2>&1; rc=$?
check "run exits 0" test $rc -eq 0
"$classify" --compact "$out/b" > "$out/bundle.json" 2> "$out/err"; rc=$?
check "bundle classified" test $rc -eq 0
check "bundle is (e)" grep -q '"class":"e"' "$out/bundle.json"

# --fronts: every propagating front with the timing the two-sided rule reads of it. The explosive
# run's fronts start at the onset; a first leg ends after it starts, and a front passes the
# middle on its first leg or the reading is that leg's end.
"$classify" --fronts --compact "$out/b" > "$out/fronts.json" 2> "$out/err"; rc=$?
check "--fronts exits 0" test $rc -eq 0
timing=$(python3 - "$out/fronts.json" <<'PY'
import json, sys
fr = json.load(open(sys.argv[1]))["fronts"]
bad = [f for f in fr if not (isinstance(f["at_onset"], bool)
                             and f["start_eps"] <= f["passes_middle_eps"] <= f["first_leg_end_eps"] <= f["end_eps"])]
print("none" if not fr else "bad" if bad else "no onset" if not any(f["at_onset"] for f in fr) else "ok")
PY
)
check "--fronts gives each front's onset and first leg ($timing)" test "$timing" = ok
# The primary front is the one the features read, and its leading-edge points give both of its
# speed readings again: the least-squares slope, and the travel between the first and the last.
edge=$(python3 - "$out/fronts.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
prim = [f for f in d["fronts"] if f["primary"]]
feat = d["features"]
if len(prim) != 1 or prim[0]["speed_over_V"] != feat["band_speed_ratio"] \
        or prim[0]["transit_speed_over_V"] != feat["band_speed_transit"]:
    print("primary front does not match the features"); sys.exit()
pts = prim[0]["leg_edge"]
e, y = [p[0] for p in pts], [p[1] for p in pts]
n, me, my = len(e), sum(e) / len(e), sum(y) / len(y)
slope = sum((a - me) * (b - my) for a, b in zip(e, y)) / sum((a - me) ** 2 for a in e)
transit = abs(y[-1] - y[0]) / (e[-1] - e[0])
ok = all(a < b for a, b in zip(e, e[1:])) and 0 < d["unit_cell_h0"] < 1 \
    and abs(abs(slope) - prim[0]["speed_over_V"]) < 1e-9 * abs(slope) \
    and abs(transit - prim[0]["transit_speed_over_V"]) < 1e-12 * transit
print("ok" if ok else f"slope {slope} transit {transit} against {prim[0]}")
PY
)
check "--fronts gives the primary front's leading-edge points ($edge)" test "$edge" = ok

"$classify" "$out/b" --features "$out/b/summary.json" 2> "$out/err"; rc=$?
check "both inputs exit 2" test $rc -eq 2
"$classify" --fronts --features "$out/b/summary.json" 2> "$out/err"; rc=$?
check "--fronts with --features exits 2" test $rc -eq 2
check "--fronts needs a bundle" grep -q -- "--fronts needs one RESULT_DIR" "$out/err"

# A point's replicates: the explosive run three times with its particles perturbed by 1 % of
# their spacing, seeds 1 to 3. Read together, the point counts three runs and its vote, and each
# reading is the mean and sample deviation of the runs that carry the majority's label, as
# compaction-classify reads each of them alone.
for seed in 1 2 3; do
  "$run" --S 0.1 --R 1e-5 --phi 0.4 --cells-per-unit 6 --eps-end 0.1 --perturbation 0.01 \
    --seed $seed --out "$out/p$seed" > /dev/null 2>&1
  "$classify" --compact "$out/p$seed" > "$out/p$seed.json"
done
"$classify" --compact "$out/p1" "$out/p2" "$out/p3" > "$out/point.json" 2> "$out/err"; rc=$?
check "a point's replicates classified" test $rc -eq 0
point=$(python3 - "$out/point.json" "$out"/p1.json "$out"/p2.json "$out"/p3.json <<'PY'
import json, statistics, sys
d = json.load(open(sys.argv[1]))
runs = [json.load(open(f)) for f in sys.argv[2:]]
p = d["point"]
labels = [r["class"] for r in runs]
top = max(sorted(set(labels)), key=labels.count)
speeds = [r["band_speed_ratio"] for r in runs if r["class"] == top]
problems = []
if (p["runs"], p["labelled"], p["class"]) != (3, 3, top):
    problems.append("runs, labelled, class %s" % [p["runs"], p["labelled"], p["class"]])
if p["share"] != labels.count(top) / 3 or p["robust"] != (labels.count(top) == 3):
    problems.append("share %s robust %s of %s" % (p["share"], p["robust"], labels))
if p["probabilities"] != {c: labels.count(c) / 3 for c in set(labels)}:
    problems.append("probabilities %s" % p["probabilities"])
b = p["band_speed_ratio"]
if b["n"] != len(speeds) or abs(b["mean"] - statistics.mean(speeds)) > 1e-12 \
        or abs(b["sd"] - statistics.stdev(speeds)) > 1e-12:
    problems.append("band_speed_ratio %s against %s" % (b, speeds))
if [r["class"] for r in d["runs"]] != labels or [r["seed"] for r in d["runs"]] != [1, 2, 3]:
    problems.append("runs %s" % [(r["class"], r["seed"]) for r in d["runs"]])
print("; ".join(problems) or "ok")
PY
)
check "the point is its runs read together ($point)" test "$point" = ok
"$classify" "$out/p1" "$out/b" 2> "$out/err"; rc=$?
check "another point's bundle exits 1" test $rc -eq 1
check "another point's bundle named with its key" grep -q "$out/b has another perturbation than $out/p1" "$out/err"
"$classify" --fronts "$out/p1" "$out/p2" 2> "$out/err"; rc=$?
check "--fronts with a point exits 2" test $rc -eq 2

"$classify" --compact --features "$out/b/summary.json" > "$out/again.json" 2> "$out/err"; rc=$?
check "features decided" test $rc -eq 0
same=$(python3 - "$out/b/summary.json" "$out/again.json" <<'PY'
import json, sys
stored = json.load(open(sys.argv[1]))["classification"]
again = json.load(open(sys.argv[2]))
print("same" if stored == again else "differ: " + ", ".join(k for k in stored if stored[k] != again.get(k)))
PY
)
check "stored features decide to the stored classification ($same)" test "$same" = same
python3 -c 'import json,sys; print(json.dumps(json.load(open(sys.argv[1]))["classification"]))' \
  "$out/b/summary.json" | "$classify" --compact --features - > "$out/stdin.json"; rc=$?
check "features from stdin" test $rc -eq 0
check "stdin gives the same" cmp -s "$out/again.json" "$out/stdin.json"

"$classify" --features "$out/none.json" 2> "$out/err"; rc=$?
check "missing file exits 1" test $rc -eq 1
check "missing file named" grep -q "cannot open $out/none.json" "$out/err"
# refused NAME CONTENT MESSAGE: --features on a file holding CONTENT exits 1 and says MESSAGE.
refused() {
  printf '%s\n' "$2" > "$out/refused.json"
  "$classify" --features "$out/refused.json" 2> "$out/err"; local rc=$?
  check "$1 exits 1" test $rc -eq 1
  check "$1 explained" grep -q -- "$3" "$out/err"
}
refused "wrong type" '{"classification": {"features": {"deflection_growth": "high"}}}' \
  "features.deflection_growth: must be a number or null"
refused "unclassified run" '{"classification": null}' "the run did not finish ok"
refused "malformed JSON" '{"features": ' "parse error"

checks_done "compaction-classify CLI"
