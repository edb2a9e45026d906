#!/usr/bin/env python3
"""The Python client (python/compaction_client) returns DataFrames and arrays, or says why it
cannot: without pandas, results() and phase_map() raise ImportError naming the interpreter and
Debian's python3-pandas instead of returning lists; without numpy, spacetime() and load_npy()
raise naming python3-numpy; frame=False and array=False give the same data as lists. A small
HTTP server in this process answers the three requests the client makes (standard library; no
compaction-server is needed).

pandas and numpy are made missing by a None entry in sys.modules (an import of it then fails as
for a module that is not installed), present by a stand-in module that records what the client
builds; where the interpreter has the real ones, the client's answers are checked with them too.
"""
import http.server
import json
import struct
import sys
import threading
import unittest

from compaction_client import Client

POINTS = [
    {"S": 0.004, "R": 1e-05, "phi": 0.4, "state": "succeeded", "class": "a", "confidence": 0.9,
     "job_id": 1},
    {"S": 0.004, "R": 0.0004, "phi": 0.4, "state": "running", "class": None, "confidence": None,
     "job_id": 2},
]
EXPORT = {"sweep": {"id": 7}, "jobs": [
    {"id": 1, "S": 0.004, "R": 1e-05, "phi": 0.4, "state": "succeeded", "scene": {"S": 0.004},
     "result": {"status": "ok", "class": "a", "confidence": 0.9}},
    {"id": 2, "S": 0.004, "R": 0.0004, "phi": 0.4, "state": "running", "scene": {"S": 0.004},
     "result": None},
]}
SPACETIME = [[0.0, 1.5, 2.25], [0.5, -1.0, 3.0]]


def npy_bytes(rows):
    """A format 1.0 .npy file of float32 values, as numpy writes it."""
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (
        len(rows), len(rows[0]))
    header += " " * ((64 - (10 + len(header) + 1) % 64) % 64) + "\n"
    flat = [v for row in rows for v in row]
    return (b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin1")
            + struct.pack("<%df" % len(flat), *flat))


class Answers(http.server.BaseHTTPRequestHandler):
    def do_GET(self):
        path = self.path.split("?")[0]
        if path == "/api/v1/phase-map":
            self.reply(json.dumps({"phi": 0.4, "points": POINTS}).encode(), "application/json")
        elif path == "/api/v1/sweeps/7/export":
            self.reply(json.dumps(EXPORT).encode(), "application/json")
        elif path == "/api/v1/jobs/1/artifacts/spacetime.npy":
            self.reply(npy_bytes(SPACETIME), "application/octet-stream")
        else:
            self.send_error(404)

    def reply(self, body, content_type):
        self.send_response(200)
        self.send_header("Content-Type", content_type)
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args):
        pass


class FakeDataFrame:
    """Stands in for pandas.DataFrame: keeps what it was built from."""

    def __init__(self, rows, columns=None):
        self.rows, self.columns = rows, columns


class FakePandas:
    DataFrame = FakeDataFrame


def importable(name):
    try:
        __import__(name)
        return True
    except ImportError:
        return False


class ClientDataFrames(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Answers)
        cls.thread = threading.Thread(target=cls.server.serve_forever, daemon=True)
        cls.thread.start()
        cls.client = Client("http://127.0.0.1:%d" % cls.server.server_address[1])

    @classmethod
    def tearDownClass(cls):
        cls.server.shutdown()
        cls.server.server_close()

    def setUp(self):
        self.saved = {m: sys.modules.get(m) for m in ("pandas", "numpy")}

    def tearDown(self):
        for module, entry in self.saved.items():
            if entry is None:
                sys.modules.pop(module, None)
            else:
                sys.modules[module] = entry

    def without(self, module):
        sys.modules[module] = None

    def assert_names_what_is_missing(self, error, module, package, method, instead):
        text = str(error)
        for part in (method, module, package, sys.executable, instead):
            self.assertIn(part, text)
        self.assertEqual(error.name, module)

    def test_without_pandas_the_frames_raise_and_never_return_lists(self):
        self.without("pandas")
        with self.assertRaises(ImportError) as caught:
            self.client.phase_map(0.4)
        self.assert_names_what_is_missing(caught.exception, "pandas", "python3-pandas",
                                          "phase_map()", "frame=False")
        with self.assertRaises(ImportError) as caught:
            self.client.results(7)
        self.assert_names_what_is_missing(caught.exception, "pandas", "python3-pandas",
                                          "results()", "frame=False")
        with self.assertRaises(ImportError):
            self.client.phase_map(0.4, frame=None)

    def test_frame_false_gives_the_servers_points_as_dicts_without_pandas(self):
        self.without("pandas")
        self.assertEqual(self.client.phase_map(0.4, frame=False), POINTS)
        rows = self.client.results(7, frame=False)
        self.assertEqual([r["job_id"] for r in rows], [1, 2])
        self.assertEqual((rows[0]["class"], rows[0]["status"]), ("a", "ok"))
        self.assertEqual((rows[1]["class"], rows[1]["status"]), (None, None))
        self.assertNotIn("scene", rows[0])

    def test_with_pandas_the_frames_are_built_from_the_same_rows(self):
        sys.modules["pandas"] = FakePandas
        frame = self.client.phase_map(0.4)
        self.assertIsInstance(frame, FakeDataFrame)
        self.assertEqual(frame.rows, POINTS)
        self.assertEqual(frame.columns, list(POINTS[0]))
        frame = self.client.results(7)
        self.assertIsInstance(frame, FakeDataFrame)
        self.assertEqual(frame.rows, self.client.results(7, frame=False))
        self.assertEqual(frame.columns[:2], ["job_id", "S"])

    def test_without_numpy_the_arrays_raise_and_array_false_gives_lists(self):
        self.without("numpy")
        with self.assertRaises(ImportError) as caught:
            self.client.spacetime(1)
        self.assert_names_what_is_missing(caught.exception, "numpy", "python3-numpy",
                                          "spacetime()", "array=False")
        with self.assertRaises(ImportError) as caught:
            self.client.load_npy(1, "spacetime.npy")
        self.assert_names_what_is_missing(caught.exception, "numpy", "python3-numpy",
                                          "load_npy()", "array=False")
        self.assertEqual(self.client.spacetime(1, array=False), SPACETIME)

    @unittest.skipUnless(importable("pandas") and importable("numpy"),
                         "this interpreter has no pandas or numpy: the cases above stand in")
    def test_with_the_real_pandas_and_numpy(self):
        import numpy
        import pandas
        frame = self.client.phase_map(0.4)
        self.assertIsInstance(frame, pandas.DataFrame)
        self.assertEqual(frame.to_dict("records")[0]["class"], "a")
        grid = self.client.spacetime(1)
        self.assertIsInstance(grid, numpy.ndarray)
        self.assertEqual((grid.shape, grid.dtype), ((2, 3), numpy.float32))
        self.assertEqual(grid.tolist(), SPACETIME)


if __name__ == "__main__":
    unittest.main()
