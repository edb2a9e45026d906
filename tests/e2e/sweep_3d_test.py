"""End to end: a sweep of the 3D column (numerics.geometry = "pseudo1d_3d") beside a 2D one at
the same point. The server takes the key, estimates the 3D run in three dimensions, a real
worker runs it with the real compaction-run (one velocity field whatever the preset asks, no
snapshots or movie), and the phase map draws each geometry on its own: the 2D map by default,
the 3D one with ?geometry=pseudo1d_3d, a bad geometry refused with 422 naming it; the run table
and the job give the 3D run its cubic hole's strut, and the run table filters by geometry."""
import signal

from e2e_lib import Env, bin_dir_from_args, check, stop

env = Env(bin_dir_from_args(), "sweep3d")
env.start_server()

point = {"S": 0.1, "R": 1e-3, "phi": 0.4}
# The 3D column at 8 cells per unit cell (the coarsest grid with a cell across its strut) to
# eps 0.01: 64 566 particles, seconds.
numerics_3d = {"cells_per_unit": 8, "eps_end": 0.01, "geometry": "pseudo1d_3d"}
numerics_2d = {"cells_per_unit": 8, "eps_end": 0.01}


def estimate(numerics):
    status, body = env.request("POST", "/api/v1/sweeps/estimate",
                               {"name": "e", "points": [point], "numerics": numerics})
    check(status == 200, "estimate answers 200: %s %s" % (status, body))
    return body["cpu_seconds"]


# The 3D column at 8 cells holds 34 rows of 16^3 - 13^3 particles (the cubic hole 16 cbrt(0.6)
# = 13.5 particles across), the 2D one 34 rows of 16^2 - 12^2 (16 sqrt(0.6) = 12.4): 17 times
# the particles, each step 8.25 times the price (the cost model's
# factor); the time steps are the same grid's. Tolerance 1 %: the steps' count differs by the
# grid spacing's rounding only.
ratio = estimate(numerics_3d) / estimate(numerics_2d)
check(abs(ratio / (1899 / 112 * 8.25) - 1) < 0.01, "3D estimate / 2D estimate = %.1f" % ratio)

s3 = env.submit({"name": "3d", "points": [point], "numerics": numerics_3d})
s2 = env.submit({"name": "2d", "points": [point], "numerics": numerics_2d})
check(s3["created"]["new"] == 1 and s2["created"]["new"] == 1, "two jobs: one per geometry")
worker = env.start_worker("w1")
for sweep in (s3, s2):
    done = env.wait_sweep_done(sweep["id"], 240)
    check(done["counts"]["succeeded"] == 1, "sweep %d succeeded: %s" % (sweep["id"], done["counts"]))

job3 = env.get("/api/v1/jobs?sweep=%d" % s3["id"])["jobs"][0]
detail = env.get("/api/v1/jobs/%d" % job3["id"])
scene = detail["scene"]
check(scene["geometry"] == "pseudo1d_3d", "the job's scene is the 3D column: %s" % scene["geometry"])
check(scene["pore_contact"] == "single_field", "the 3D column runs one velocity field (the preset's "
      "auto resolved): %s" % scene["pore_contact"])
check(scene["snapshot_eps"] == [] and scene["movie_d_eps"] == 0,
      "the 3D column runs without snapshots or movie: %s %s" % (scene["snapshot_eps"], scene["movie_d_eps"]))
result = detail["result"]
check(result["status"] in ("ok", "unstable"), "the 3D run has a result: %s" % result["status"])
check(result["summary"]["params"]["geometry"] == "pseudo1d_3d", "the summary names the geometry")
names = {a["name"] for a in env.get("/api/v1/jobs/%d/artifacts" % job3["id"])["artifacts"]}
for required in ("summary.json", "frames.csv", "spacetime.npy"):
    check(required in names, "artifact %s of the 3D run (have %s)" % (required, names))

job2 = env.get("/api/v1/jobs?sweep=%d" % s2["id"])["jobs"][0]
default_map = [p["job_id"] for p in env.get("/api/v1/phase-map?phi=0.4")["points"]]
check(default_map == [job2["id"]], "the default map is the 2D one: %s" % default_map)
map_3d = [p["job_id"] for p in env.get("/api/v1/phase-map?phi=0.4&geometry=pseudo1d_3d")["points"]]
check(map_3d == [job3["id"]], "the 3D map holds the 3D run only: %s" % map_3d)
# Cells across the strut: 8 (1 - cbrt(0.6)) = 1.25 for the cubic hole, 8 (1 - sqrt(0.6)) = 1.80
# for the square one (to the 3 digits the check reads).
answer_3d = env.get("/api/v1/phase-map?phi=0.4&geometry=pseudo1d_3d")
check(round(answer_3d["points"][0]["cells_per_strut"], 3) == 1.253 and
      round(answer_3d["summaries"][0]["cells_per_strut"], 3) == 1.253,
      "the 3D run's strut: %s" % answer_3d["points"][0]["cells_per_strut"])
check(round(env.get("/api/v1/phase-map?phi=0.4")["points"][0]["cells_per_strut"], 3) == 1.803,
      "the 2D run's strut")
check(round(detail["cells_per_strut"], 3) == 1.253, "GET /jobs/{id}: the 3D run's strut: %s" % detail["cells_per_strut"])
table = env.get("/api/v1/jobs?format=table&geometry=pseudo1d_3d")
check(table["total"] == 1 and table["rows"][0]["id"] == job3["id"] and
      table["rows"][0]["geometry"] == "pseudo1d_3d" and round(table["rows"][0]["cells_per_strut"], 3) == 1.253,
      "the run table's 3D filter keeps the 3D run with its strut: %s" % table)
table_2d = env.get("/api/v1/jobs?format=table&geometry=pseudo1d")
check(table_2d["total"] == 1 and round(table_2d["rows"][0]["cells_per_strut"], 3) == 1.803,
      "the run table's 2D run: %s" % table_2d)
regions = env.get("/api/v1/phase-map/regions?phi=0.4&geometry=pseudo1d_3d")
check(regions["runs"] <= 1, "the 3D regions count the 3D runs only: %s" % regions["runs"])
check(env.get("/api/v1/phase-map?phi=0.4&geometry=full2d")["points"] == [], "no full2d runs")
status, body = env.request("GET", "/api/v1/phase-map?phi=0.4&geometry=cube")
check(status == 422 and body["error"]["field"] == "geometry", "a bad geometry: 422 %s" % body)

check(stop(worker, signal.SIGTERM) == 0, "the worker exits 0 on SIGTERM")
check(stop(env.server, signal.SIGTERM) == 0, "the server exits 0 on SIGTERM")
print("ok")
