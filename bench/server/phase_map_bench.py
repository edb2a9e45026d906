#!/usr/bin/env python3
"""The 10 000-job phase map after a change, for several server binaries in one run: for each,
a server on a temporary database with 10 000 jobs at phi 0.4 (succeeded, by queue_bench's fake
workers) and 20 000 at other phis, then 20 GETs of /phase-map?phi=0.4 each after a heartbeat
(so no cached answer serves it): median time and answer size, with the load average.

usage: bench/server/phase_map_bench.py BIN_DIR [BIN_DIR ...]   (prints one line per binary)
"""
import json
import os
import sys
import tempfile

import queue_bench as q
from http_bench import Server

for b in sys.argv[1:]:
    s = Server(b, tempfile.mkdtemp(prefix="phase-map-bench-"))
    try:
        engine = json.loads(s.call("GET", "/api/v1/health")[1])["engine_version"]
        ids = [q.create(s, q.sweep_body("m%d" % k, k, 0.4, priority=10)) for k in range(5)]
        for k in range(10):
            q.create(s, q.sweep_body("o%d" % k, 0, 0.5 + 0.01 * k))
        while any(json.loads(s.call("GET", "/api/v1/sweeps/%d" % i)[1])["counts"]["queued"] > 0
                  for i in ids):
            q.cycles(s, engine, 32, 3.0)
        t, size = q.one_reader(s, "/api/v1/phase-map?phi=0.4", engine, n=20)
        print("%s: 10 000-job map after a change: median %.1f ms, %d bytes, load %.1f"
              % (b, t * 1e3, size, os.getloadavg()[0]))
    finally:
        s.stop()
