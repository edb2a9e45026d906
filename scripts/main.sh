#!/usr/bin/env bash
# The main job: installs the dependencies, builds, starts the sweep server on ./data/compaction.db
# and one worker per core, prints the dashboard's phase map and runs until Ctrl-C (then stops the
# workers and the server cleanly). On the first start (an empty database) it imports the
# committed map of the paper's Fig. 2 (studies/phase_map: 200 runs at the default preset), so
# the map has something worth looking at at once, and submits a small demonstration sweep at the
# default preset where runs are cheap (large S: a few minutes on two cores); it says when the
# demonstration is done.
#   COMPACTION_PORT (default 8080), COMPACTION_WORKERS (default: nproc), COMPACTION_DATA (default
#   ./data) change the defaults; COMPACTION_SKIP_BUILD=1 with COMPACTION_BIN=DIR runs binaries
#   built elsewhere.
set -euo pipefail
cd "$(dirname "$0")/.."

if [ -z "${COMPACTION_SKIP_BUILD:-}" ]; then
  scripts/install-deps.sh
  scripts/build.sh release
fi

port="${COMPACTION_PORT:-8080}"
n_workers="${COMPACTION_WORKERS:-$(nproc)}"
bin="${COMPACTION_BIN:-$PWD/build/bin}"
data="${COMPACTION_DATA:-data}"
mkdir -p "$data/logs"
url="http://127.0.0.1:$port"

pids=()
poller=""
stop_all() {
  trap - INT TERM EXIT
  echo
  if [ -n "$poller" ]; then kill -TERM "$poller" 2>/dev/null || true; wait "$poller" 2>/dev/null || true; fi
  echo "stopping ${#pids[@]} process(es)..."
  # Workers first (each releases its lease so the job requeues at once), then the server.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
    kill -TERM "${pids[$i]}" 2>/dev/null || true
    wait "${pids[$i]}" 2>/dev/null || true
  done
  echo "stopped; the database stays in $data/compaction.db"
}
trap stop_all INT TERM EXIT

"$bin/compaction-server" --db "$data/compaction.db" --host 127.0.0.1 --port "$port" \
  >>"$data/logs/server.log" 2>&1 &
pids=("$!")
for _ in $(seq 100); do
  curl -fsS "$url/api/v1/health" >/dev/null 2>&1 && break
  kill -0 "${pids[0]}" 2>/dev/null || { echo "the server did not start:"; tail -5 "$data/logs/server.log"; exit 1; }
  sleep 0.1
done
curl -fsS "$url/api/v1/health" >/dev/null || { echo "the server does not answer on $url"; exit 1; }

# Workers after the server (stop_all stops them first: it walks the list backwards).
for i in $(seq "$n_workers"); do
  "$bin/compaction-worker" --server "$url" --name "local-$i" >>"$data/logs/worker-$i.log" 2>&1 &
  pids+=("$!")
done

sweeps=$(curl -fsS "$url/api/v1/sweeps?limit=1" | python3 -c 'import json,sys; print(json.load(sys.stdin)["total"])')
demo=""
if [ "$sweeps" = "0" ]; then
  # The committed Fig. 2 map, as another server would send it (the submit token is open here).
  curl -fsS -X POST "$url/api/v1/imports" -H 'Content-Type: application/json' \
    --data-binary @studies/phase_map/results/sweep-2.export.json >/dev/null
  echo "imported the committed Fig. 2 map (200 runs at phi = 0.4, default preset)"
  demo=$(curl -fsS -X POST "$url/api/v1/sweeps" -H 'Content-Type: application/json' -d '{
      "name": "demo: large S at the default preset (cheap runs beside the imported Fig. 2 map)",
      "S": {"min": 3e-2, "max": 1e-1, "n": 3, "scale": "log"},
      "R": {"min": 1e-5, "max": 1e-2, "n": 4, "scale": "log"},
      "phi": 0.4,
      "numerics": {"preset": "default", "eps_end": 0.3}}' |
    python3 -c 'import json,sys; print(json.load(sys.stdin)["id"])')
  echo "submitted the demonstration sweep $demo: 12 runs at phi = 0.4, S 0.03 to 0.1, R 1e-5 to 1e-2"
fi

echo "phase map: $url/#/map?phi=0.4   (sweeps: $url/#/sweeps, API: $url/api/v1/openapi.yaml)"
echo "server and $n_workers worker(s) running; logs in $data/logs/. Ctrl-C stops them."
if [ -n "$demo" ]; then
  # Says when the demonstration is done (a background poll that ends with it, with the server, or
  # at once when stop_all stops it: its sleep is a child it waits for and kills on SIGTERM).
  (
    nap=""
    trap '[ -z "$nap" ] || kill "$nap" 2>/dev/null; exit 0' TERM
    while :; do
      sleep 5 & nap=$!
      wait "$nap"
      state=$(curl -fsS "$url/api/v1/sweeps/$demo" 2>/dev/null | python3 -c '
import json, sys
c = json.load(sys.stdin)["counts"]
left = c.get("queued", 0) + c.get("running", 0)
print("done %d %d" % (c.get("succeeded", 0), c.get("failed", 0)) if left == 0 else "running")') || exit 0
      case "$state" in
        done*) set -- $state
               echo "the demonstration sweep is done: $2 runs succeeded, $3 failed; see $url/#/map?phi=0.4"
               exit 0 ;;
      esac
    done
  ) &
  poller=$!
fi
wait "${pids[0]}"
