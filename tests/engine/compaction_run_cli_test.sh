#!/usr/bin/env bash
# compaction-run end to end: help, clear errors with exit 2 for bad input, a small run that
# writes a complete bundle, JSON progress lines, and a scene file overridden by flags.
set -u
run="$1"
source "$(dirname "$0")/../lib/cli_checks.sh"

"$run" --help > "$out/help" 2>&1; rc=$?
check "help exits 0" test $rc -eq 0
check "help documents --cells-per-unit" grep -q -- "--cells-per-unit" "$out/help"

"$run" --phi 0.9 --out "$out/x" 2> "$out/err"; rc=$?
check "phi out of range exits 2" test $rc -eq 2
check "phi error names the flag" grep -q -- "--phi (phi): must be in \[0.2, 0.8\]" "$out/err"
check "nothing written on bad input" test ! -e "$out/x"

"$run" --S abc --out "$out/x" 2> "$out/err"; rc=$?
check "non-number exits 2" test $rc -eq 2
check "non-number message" grep -q -- "--S: expected a finite number, got 'abc'" "$out/err"

"$run" --S 0.05 2> "$out/err"; rc=$?
check "missing --out exits 2" test $rc -eq 2
check "missing --out message" grep -q -- "--out: required" "$out/err"

"$run" --check --S 4e-3 --cells-per-unit 16 --pore-contact split_fields > "$out/check" 2> "$out/err"; rc=$?
check "check of a valid scene exits 0 without --out" test $rc -eq 0
check "check prints the scene with its grid" grep -q '"grid":{"cells_per_strut":3.6' "$out/check"
check "check prints pore_contact" grep -q '"pore_contact":"split_fields"' "$out/check"
"$run" --check --S 4e-3 --cells-per-unit 12 --pore-contact split_fields > "$out/check" 2> "$out/err"; rc=$?
check "check of an invalid scene exits 2" test $rc -eq 2
check "check names the field" grep -q -- "--pore-contact (pore_contact): split_fields needs at least 3 grid cells" "$out/err"

"$run" --bogus 1 --out "$out/x" 2> "$out/err"; rc=$?
check "unknown flag exits 2" test $rc -eq 2

# Presets (compaction/presets.hpp): the runner's defaults are the default preset's; --preset
# names one; an unknown one names the presets; flags beside a preset override it key by key.
"$run" --check > "$out/check" 2> "$out/err"; rc=$?
check "the defaults are a valid scene" test $rc -eq 0
check "the defaults are the default preset's numerics" grep -q '"cells_per_strut":4.5,.*"pore_contact":"auto"' "$out/check"
"$run" --check --preset fast > "$out/check" 2> "$out/err"; rc=$?
check "--preset fast" grep -q '"cells_per_strut":1.8,.*"pore_contact":"single_field"' "$out/check"
"$run" --preset quick --out "$out/x" 2> "$out/err"; rc=$?
check "an unknown preset exits 2" test $rc -eq 2
check "an unknown preset names the presets" grep -q -- "--preset: unknown preset 'quick': the presets are fast, default, reference" "$out/err"
# Every default a geometry cannot take is its own: a 3D scene without numerics flags is valid.
"$run" --check --geometry pseudo1d_3d > "$out/check" 2> "$out/err"; rc=$?
check "a 3D scene with its defaults is valid" test $rc -eq 0
check "3D defaults: no snapshots, no movie" grep -q '"movie_d_eps":0.0.*"snapshot_eps":\[\]' "$out/check"
"$run" --check --geometry pseudo1d_3d --movie-d-eps 0.02 > "$out/check" 2> "$out/err"; rc=$?
check "a flag a geometry cannot take exits 2" test $rc -eq 2
check "it names the flag and the geometry" grep -q -- "--movie-d-eps (movie_d_eps) with --geometry pseudo1d_3d" "$out/err"

echo '{"S": 0.05, "R": 0.001, "phi": 0.4, "cells_per_unit": 5, "eps_end": 0.9}' > "$out/scene.json"
"$run" --scene "$out/scene.json" --eps-end 0.01 --progress json --out "$out/b" > "$out/progress" 2> "$out/err"; rc=$?
check "run exits 0" test $rc -eq 0
check "bundle has summary" test -s "$out/b/summary.json"
check "flag overrides scene file" grep -q '"eps_end": 0.01' "$out/b/summary.json"
check "scene file value kept" grep -q '"cells_per_unit": 5' "$out/b/summary.json"
check "json progress has start" grep -q '"event":"start"' "$out/progress"
check "json progress has progress" grep -q '"event":"progress"' "$out/progress"
check "json progress has done ok" grep -q '"event":"done".*"status":"ok"\|"status":"ok".*"event":"done"' "$out/progress"
check "the summary names the preset and what was overridden" grep -q '"overridden": {' "$out/b/summary.json"
check "cells_per_unit overrides the preset's grid" grep -A4 '"overridden": {' "$out/b/summary.json" | grep -q '"cells_per_unit": 5'

# A run says what it found, in one line on stdout.
"$run" --S 0.05 --R 0.001 --cells-per-unit 5 --eps-end 0.01 --progress none --out "$out/d" > "$out/said" 2> "$out/err"; rc=$?
check "a quiet run exits 0" test $rc -eq 0
check "the last line says the class, its confidence and runner-up, and N_r" grep -q "^compaction-run: \(class [a-f] (confidence [0-9.]*, runner-up [a-f-])\|unclassified (runner-up [a-f-])\), N_r [0-9-]*.*; bundle $out/d\$" "$out/said"
check "spacetime.png is a figure (900 x 440)" python3 -c "import struct,sys; d=open('$out/d/spacetime.png','rb').read(24); sys.exit(0 if struct.unpack('>II', d[16:24]) == (900, 440) else 1)"

echo '{"S": 0.05, "phi": 0.4, "typo": 1}' > "$out/bad.json"
"$run" --scene "$out/bad.json" --out "$out/c" 2> "$out/err"; rc=$?
check "unknown scene key exits 2" test $rc -eq 2
check "unknown scene key named" grep -q "typo" "$out/err"

# Checkpoints (docs/runner.md): flags checked, a checkpoint of another scene refused with exit 4,
# a resumed run's frames the same as the uninterrupted run's above.
"$run" --S 0.05 --checkpoint-every 5 --out "$out/x" 2> "$out/err"; rc=$?
check "checkpoint-every without checkpoint exits 2" test $rc -eq 2
check "checkpoint-every message" grep -q -- "--checkpoint-every: needs --checkpoint FILE" "$out/err"
"$run" --S 0.05 --checkpoint "$out/c.ckpt" --checkpoint-every -1 --out "$out/x" 2> "$out/err"; rc=$?
check "negative checkpoint-every exits 2" test $rc -eq 2
check "checkpoint-every range message" grep -q -- "--checkpoint-every: must be in \[0, 1e+07\], got -1" "$out/err"
"$run" --S 0.05 --resume "$out/none.ckpt" --out "$out/x" 2> "$out/err"; rc=$?
check "resume of a missing file exits 2" test $rc -eq 2
check "resume message" grep -q -- "--resume: no such file" "$out/err"
"$run" --help > "$out/help" 2>&1
check "help documents --checkpoint-every" grep -q -- "--checkpoint-every SECONDS" "$out/help"
# a checkpoint before every step: the file holds the state before the run's last step
"$run" --scene "$out/scene.json" --eps-end 0.01 --checkpoint "$out/c.ckpt" --checkpoint-every 0 \
  --progress json --out "$out/d" > "$out/progress" 2> "$out/err"; rc=$?
check "no checkpoint without a stop at interval 0" test ! -e "$out/c.ckpt"
"$run" --scene "$out/scene.json" --eps-end 0.01 --checkpoint "$out/c.ckpt" --checkpoint-every 1e-9 \
  --progress json --out "$out/d" > "$out/progress" 2> "$out/err"; rc=$?
check "run with checkpoints exits 0" test $rc -eq 0
check "checkpoint lines" grep -q '"event":"checkpoint"' "$out/progress"
check "checkpoint written" test -s "$out/c.ckpt"
"$run" --scene "$out/scene.json" --eps-end 0.01 --S 0.04 --resume "$out/c.ckpt" --out "$out/e" 2> "$out/err"; rc=$?
check "checkpoint of another scene exits 4" test $rc -eq 4
check "refusal names the field" grep -q -- "--resume: the checkpoint is of another scene: S is 0.05 there and 0.04 here" "$out/err"
check "nothing written on refusal" test ! -e "$out/e/summary.json"
"$run" --scene "$out/scene.json" --eps-end 0.01 --resume "$out/c.ckpt" --progress json --out "$out/f" > "$out/progress" 2> "$out/err"; rc=$?
check "resumed run exits 0" test $rc -eq 0
check "resumed line" grep -q '"event":"resumed"' "$out/progress"
check "resumed frames equal the uninterrupted run's" cmp -s "$out/b/frames.csv" "$out/f/frames.csv"
check "resumed map equals the uninterrupted run's" cmp -s "$out/b/spacetime.npy" "$out/f/spacetime.npy"
# the 3D column's checkpoints as 2D's: written before every step, the last one resumed
col3d=(--geometry pseudo1d_3d --S 0.05 --R 1e-3 --phi 0.5 --n-rows 4 --cells-per-unit 6
       --eps-end 0.01 --d-eps 0.002 --progress json)
"$run" "${col3d[@]}" --out "$out/g3" > /dev/null 2> "$out/err"; rc=$?
check "3D run exits 0" test $rc -eq 0
"$run" "${col3d[@]}" --checkpoint "$out/c3.ckpt" --checkpoint-every 1e-9 --out "$out/h3" \
  > "$out/progress" 2> "$out/err"; rc=$?
check "3D run with checkpoints exits 0" test $rc -eq 0
check "3D checkpoint lines" grep -q '"event":"checkpoint"' "$out/progress"
"$run" "${col3d[@]}" --resume "$out/c3.ckpt" --out "$out/i3" > "$out/progress" 2> "$out/err"; rc=$?
check "3D resumed run exits 0" test $rc -eq 0
check "3D resumed line" grep -q '"event":"resumed"' "$out/progress"
check "3D resumed frames equal the uninterrupted run's" cmp -s "$out/g3/frames.csv" "$out/i3/frames.csv"
check "3D resumed map equals the uninterrupted run's" cmp -s "$out/g3/spacetime.npy" "$out/i3/spacetime.npy"
"$run" "${col3d[@]}" --S 0.04 --resume "$out/c3.ckpt" --out "$out/j3" 2> "$out/err"; rc=$?
check "3D checkpoint of another scene exits 4" test $rc -eq 4

checks_done
