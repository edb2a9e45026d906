#!/usr/bin/env bash
# The main job: installs the dependencies, builds, starts the sweep server on ./data/compaction.db
# and one worker per core, submits a small demonstration sweep when the database is empty, prints
# the dashboard's address and runs until Ctrl-C (then stops the workers and the server cleanly).
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
stop_all() {
  trap - INT TERM EXIT
  echo
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
if [ "$sweeps" = "0" ]; then
  curl -fsS -X POST "$url/api/v1/sweeps" -H 'Content-Type: application/json' -d '{
      "name": "demo: phi = 0.4, coarse log grid, fast preset",
      "S": {"min": 1e-3, "max": 1e-1, "n": 4, "scale": "log"},
      "R": {"min": 1e-5, "max": 1e-1, "n": 5, "scale": "log"},
      "phi": 0.4,
      "numerics": {"preset": "fast"}}' >/dev/null
  echo "submitted the demonstration sweep (20 jobs at phi = 0.4)"
fi

echo "dashboard: $url/   (API: $url/api/v1/openapi.yaml, phase map: $url/api/v1/phase-map?phi=0.4)"
echo "server and $n_workers worker(s) running; logs in $data/logs/. Ctrl-C stops them."
wait "${pids[0]}"
