"""End to end: an adaptive sweep through a real server and two real workers. It starts with its
initial grid, grows as results arrive where the labels (real runs, tiny numerics) disagree, never
holds more jobs than its budget nor more than in_flight open at once past the grid, finishes by
itself, and carries on after kill -9 of the server; its export lists every job."""
import math
import signal

from e2e_lib import Env, TINY, bin_dir_from_args, check

BUDGET, IN_FLIGHT = 16, 3
env = Env(bin_dir_from_args(), "adaptive")
env.start_server("--lease-seconds", "10", "--rescue-interval", "0.5")
port = env.port
env.start_worker("w1")
env.start_worker("w2")

# S from 0.02 to 0.1 and R from 1e-4 to 1e-1 cross several classes even in runs this short.
body = {"name": "adaptive", "phi": 0.4, "numerics": TINY,
        "adaptive": {"S": {"min": 0.02, "max": 0.1}, "R": {"min": 1e-4, "max": 1e-1},
                     "initial": {"S": 2, "R": 3}, "resolution_decades": 0.1,
                     "budget": BUDGET, "in_flight": IN_FLIGHT}}
status, out = env.request("POST", "/api/v1/sweeps", dict(body, S=0.05))
check(status == 422 and out["error"]["field"] == "S", "S beside adaptive is refused: %s" % out)
status, out = env.request("POST", "/api/v1/sweeps", dict(body, adaptive=dict(body["adaptive"], budget=5)))
check(status == 422 and out["error"]["field"] == "adaptive.budget", "a budget below the grid: %s" % out)

sweep = env.submit(body)
check(sweep["counts"]["total"] == 6, "the initial 2 x 3 grid: %s" % sweep["counts"])
sid = sweep["id"]

seen_totals = []
def progressed():
    s = env.get("/api/v1/sweeps/%d" % sid)
    c = s["counts"]
    seen_totals.append(c["total"])
    check(c["total"] <= BUDGET, "never beyond the budget: %s" % c)
    return c["succeeded"] + c["failed"] >= 4
env.wait_for(progressed, 120, "four results")

env.server.send_signal(signal.SIGKILL)  # mid-sweep: the restart plans on from the database
env.server.wait()
env.start_server("--lease-seconds", "10", "--rescue-interval", "0.5", "--port", str(port))


def finished():
    s = env.get("/api/v1/sweeps/%d" % sid)
    c = s["counts"]
    seen_totals.append(c["total"])
    check(c["total"] <= BUDGET, "never beyond the budget: %s" % c)
    if c["queued"] + c["running"] or s["state"] != "done":
        return None
    # The sweep reads done for a moment between a result and the points it makes the planner
    # add; the plan tells the two apart ("planning").
    plan = env.get("/api/v1/sweeps/%d/plan" % sid)
    return s if plan["state"] in ("resolved", "budget_spent", "unresolved") else None
done = env.wait_for(finished, 240, "the adaptive sweep to finish")
check(seen_totals == sorted(seen_totals), "the total only grows: %s" % seen_totals)

jobs = env.get("/api/v1/sweeps/%d/export?format=json" % sid)["jobs"]
check(len(jobs) == done["counts"]["total"], "the export lists every job")
labels = {j["result"]["class"] if j["result"] else None for j in jobs[:6]}
if len(labels) > 1:
    check(done["counts"]["total"] > 6, "the initial labels differ (%s), so the sweep grew" % labels)
# Every point is inside the box, and no two are closer than the resolution on both axes.
for j in jobs:
    check(0.02 - 1e-12 <= j["S"] <= 0.1 + 1e-12 and 1e-4 - 1e-15 <= j["R"] <= 0.1 + 1e-12,
          "job %d inside the box" % j["id"])
for a in jobs:
    for b in jobs:
        if a["id"] < b["id"]:
            dS = abs(math.log10(a["S"] / b["S"]))
            dR = abs(math.log10(a["R"] / b["R"]))
            check(dS >= 0.1 - 1e-9 or dR >= 0.1 - 1e-9, "jobs %d and %d too close" % (a["id"], b["id"]))
# The plan over HTTP: finished, so resolved, out of budget or unresolved, never running; its
# runs are the sweep's, and a grid sweep has no plan.
plan = env.get("/api/v1/sweeps/%d/plan" % sid)
check(plan["state"] in ("resolved", "budget_spent", "unresolved"), "a finished plan: %s" % plan)
check(plan["runs"]["done"] == len(jobs) and plan["runs"]["pending"] == 0, "the plan's runs: %s" % plan)
check(plan["state"] != "budget_spent" or len(jobs) == BUDGET, "budget_spent at %d runs" % len(jobs))
check(plan["lattice"]["points"] == plan["lattice"]["S"] * plan["lattice"]["R"] >= len(jobs),
      "the full grid holds every run: %s" % plan["lattice"])
grid = env.submit({"name": "grid", "phi": 0.4, "numerics": TINY, "S": 0.05, "R": 1e-3})
status, out = env.request("GET", "/api/v1/sweeps/%d/plan" % grid["id"])
check(status == 409 and out["error"]["field"] == "id", "a grid sweep has no plan: %s" % out)
print("adaptive sweep: %d runs, initial labels %s, plan %s" % (len(jobs), sorted(map(str, labels)), plan["state"]))
