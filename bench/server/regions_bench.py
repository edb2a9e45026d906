#!/usr/bin/env python3
"""GET /phase-map/regions on the 10 000-job map after a change: a server on a temporary
database with 10 000 labelled jobs at phi 0.4 (5 sweeps of 2 000, completed by queue_bench's
fake workers, class a with confidence 0.9) and 4 000 at other phis, then 10 GETs of the regions
at each grid size, each after a heartbeat (so no cached answer serves it): median time and
answer size, with the load average; and the 2 000 runs of one sweep at the default grid.

usage: bench/server/regions_bench.py BIN_DIR   (prints one line per case)
"""
import json
import os
import sys
import tempfile

import queue_bench as q
from http_bench import Server

s = Server(sys.argv[1], tempfile.mkdtemp(prefix="regions-bench-"))
try:
    engine = json.loads(s.call("GET", "/api/v1/health")[1])["engine_version"]
    ids = [q.create(s, q.sweep_body("m%d" % k, k, 0.4, priority=10)) for k in range(5)]
    for k in range(2):
        q.create(s, q.sweep_body("other%d" % k, 0, 0.5 + 0.01 * k))
    while any(json.loads(s.call("GET", "/api/v1/sweeps/%d" % i)[1])["counts"]["queued"] > 0
              for i in ids):
        q.cycles(s, engine, 32, 3.0)
    for path in ["/api/v1/phase-map/regions?phi=0.4&grid=64",
                 "/api/v1/phase-map/regions?phi=0.4",
                 "/api/v1/phase-map/regions?phi=0.4&grid=256",
                 "/api/v1/phase-map/regions?phi=0.4&sweep=%d" % ids[0]]:
        t, size = q.one_reader(s, path, engine, n=10)
        print("%s: median %.1f ms, %d bytes, load %.1f" % (path, t * 1e3, size, os.getloadavg()[0]))
finally:
    s.stop()
