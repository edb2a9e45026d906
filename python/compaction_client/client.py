"""Client of the compaction-sweep REST API (/api/v1, docs/service.md): a submitter and reader,
never a worker. Standard library only, but for the DataFrames (pandas) and arrays (numpy) some
methods return, imported when they are called (optional.py)."""
import json
import os
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Iterable, Mapping

from . import npy
from .optional import require
from .progress import Bar

# The result fields a row of Client.results carries beside the job's own fields: the result
# columns of the server's CSV export, plus the classifier's features.
RESULT_COLUMNS = ("status", "reason", "class", "confidence", "runner_up", "n_reflections",
                  "band_speed_ratio", "features", "eps_reached", "wall_seconds",
                  "source_revision")

# The server answers at most this many rows per page of a list (GET /sweeps, GET /jobs).
PAGE_LIMIT = 1000


class ApiError(Exception):
    """An error answer of the server: the HTTP status and the server's own words.

    status: the HTTP status (401, 404, 413, 422, ...); message: the server's message; field: the
    part of the request it is about ("phi", "points[2].S", "Authorization"; "" when none);
    details: every problem as [{"field", "message"}] when the server listed several, else [];
    error_id: the id a 500 answer names in the server's log, else None."""

    def __init__(self, status, message, field="", details=None, error_id=None, method="",
                 path=""):
        self.status = status
        self.message = message
        self.field = field
        self.details = details or []
        self.error_id = error_id
        self.method = method
        self.path = path
        super().__init__(str(self))

    def __str__(self):
        where = "%s %s: " % (self.method, self.path) if self.method else ""
        problems = self.details or [{"field": self.field, "message": self.message}]
        said = "; ".join(("%s: %s" % (p["field"], p["message"])) if p["field"] else p["message"]
                         for p in problems)
        if self.error_id:
            said += " (error id %s)" % self.error_id
        return "%s%d %s" % (where, self.status, said)

    @classmethod
    def from_answer(cls, status, payload, method, path):
        try:
            error = json.loads(payload)["error"]
            return cls(status, error["message"], error.get("field", ""), error.get("details"),
                       error.get("id"), method, path)
        except (ValueError, KeyError, TypeError):
            text = payload.decode("utf-8", "replace").strip()[:500]
            return cls(status, text or "no message", "", None, None, method, path)


def log_axis(lo, hi, n):
    """A grid axis of n values from lo to hi, evenly spaced in log (the server expands it)."""
    return {"min": lo, "max": hi, "n": n, "scale": "log"}


def linear_axis(lo, hi, n):
    """A grid axis of n values from lo to hi, evenly spaced (the server expands it)."""
    return {"min": lo, "max": hi, "n": n, "scale": "linear"}


def _json_default(value):
    # numpy scalars and arrays (float64(0.1), array([...])) become Python numbers and lists.
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError("%s is not a JSON value" % type(value).__name__)


def _axis(value):
    # What the API takes as it is: a number, a list or {min, max, n, scale}; any other
    # iterable (a tuple, a range, a numpy array) is sent as a list. The server judges the values.
    if isinstance(value, (str, bytes, Mapping, list)) or not isinstance(value, Iterable):
        return value
    return list(value)


def _point(i, p):
    if isinstance(p, Mapping):
        return dict(p)
    values = list(p)
    if len(values) != 3:
        raise ValueError("points[%d]: expected {S, R, phi} or (S, R, phi), got %d values"
                         % (i, len(values)))
    return {"S": values[0], "R": values[1], "phi": values[2]}


def _replicates(value):
    # (n, perturbation), {"n", "perturbation"} or n alone (a random structure needs no
    # perturbation): the request's "replicates" object.
    if isinstance(value, Mapping):
        return dict(value)
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise ValueError("replicates: expected (n, perturbation), got %d values" % len(value))
        return {"n": value[0], "perturbation": value[1]}
    return {"n": value}


CLASSES = ("a", "b", "c", "d", "e", "f")
SPREAD_READINGS = ("band_speed_ratio", "band_speed_early", "band_speed_lead",
                   "band_speed_transit", "n_reflections")
POINT_COLUMNS = (["point_id", "S", "R", "phi", "cells_per_unit", "cells_per_strut", "eps_end",
                  "structure", "runs", "finished", "labelled", "label", "share", "robust"]
                 + ["p_" + c for c in CLASSES]
                 + [r + suffix for r in SPREAD_READINGS for suffix in ("_mean", "_sd", "_n")]
                 + ["jobs"])


def _point_row(point):
    # A point of the server's answer as flat columns (POINT_COLUMNS).
    row = {k: point[k] for k in POINT_COLUMNS if k in point}
    for c in CLASSES:
        row["p_" + c] = point["probabilities"].get(c, 0.0)
    for r in SPREAD_READINGS:
        spread = point.get(r) or {}
        row[r + "_mean"] = spread.get("mean")
        row[r + "_sd"] = spread.get("sd")
        row[r + "_n"] = spread.get("n", 0)
    return {k: row.get(k) for k in POINT_COLUMNS}


# The run table's filters that take a (min, max) pair in Client.runs.
RANGE_FILTERS = ("S", "R", "confidence", "n_reflections", "band_speed_ratio")


def _query_value(value):
    # A value of a query parameter as the server reads it: lists comma-separated, booleans
    # true/false, numbers in full precision; None leaves the parameter out.
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, (list, tuple, set, frozenset)):
        return ",".join(_query_value(v) for v in value)
    if hasattr(value, "item"):  # a numpy scalar
        value = value.item()
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def _id(sweep_or_id):
    # A sweep as the server answers it ({"id": ...}) or its id.
    return sweep_or_id["id"] if isinstance(sweep_or_id, Mapping) else sweep_or_id


def _frame(rows, columns, frame, what):
    # frame=False: the rows, a list of dicts; otherwise a pandas DataFrame, and without pandas
    # an ImportError that says so (never the rows in its place).
    if frame is False:
        return rows
    pandas = require("pandas", "%s with frame=True (the default)" % what,
                     "frame=False gives a list of dicts instead")
    return pandas.DataFrame(rows, columns=columns)


class Client:
    """A connection to one compaction-server.

    url: the server's address (http://127.0.0.1:8080; a trailing /api/v1 is accepted).
    token: the submit token, needed to submit and cancel when the server has one; None reads
    COMPACTION_SUBMIT_TOKEN from the environment (as the server does). Reading needs none.
    timeout: seconds one HTTP request may take."""

    def __init__(self, url, token=None, timeout=60.0):
        url = url.rstrip("/")
        if url.endswith("/api/v1"):
            url = url[:-len("/api/v1")]
        if not url.startswith(("http://", "https://")):
            raise ValueError("url must start with http:// or https://, got %r" % url)
        self.url = url
        self.token = token if token is not None else os.environ.get("COMPACTION_SUBMIT_TOKEN")
        self.timeout = timeout

    def __repr__(self):
        return "Client(%r)" % self.url

    # --- HTTP ---
    def _call(self, method, path, body=None, query=None, write=False):
        """The answer's bytes; an error answer raises ApiError, an unreachable server
        ConnectionError."""
        path = "/api/v1" + path
        if query:
            path += "?" + urllib.parse.urlencode(
                {k: v for k, v in query.items() if v is not None})
        headers = {}
        data = None
        if body is not None:
            data = json.dumps(body, allow_nan=False, default=_json_default).encode()
            headers["Content-Type"] = "application/json"
        if write and self.token:
            headers["Authorization"] = "Bearer " + self.token
        request = urllib.request.Request(self.url + path, data=data, method=method,
                                         headers=headers)
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as answer:
                return answer.read()
        except urllib.error.HTTPError as e:
            with e:
                payload = e.read()
            raise ApiError.from_answer(e.code, payload, method, path) from None
        except urllib.error.URLError as e:
            raise ConnectionError("cannot reach %s: %s" % (self.url, e.reason)) from None

    def _json(self, method, path, body=None, query=None, write=False):
        return json.loads(self._call(method, path, body, query, write))

    def _all_pages(self, path, key, query):
        items, offset = [], 0
        while True:
            page = self._json("GET", path, query=dict(query, limit=PAGE_LIMIT, offset=offset))
            items += page[key]
            offset += len(page[key])
            if not page[key] or offset >= page["total"]:
                return items

    # --- the service ---
    def health(self):
        """{"status", "engine_version", "source_revision", "jobs": {state: count}}."""
        return self._json("GET", "/health")

    def presets(self):
        """The numerics presets: {"presets": [{name, description, cells_per_unit, ...}],
        "default": name}."""
        return self._json("GET", "/presets")

    def limits(self):
        """What a sweep request may hold ({"sweep": {...}, "scene": {...}}); the server checks
        every request against these itself."""
        return self._json("GET", "/limits")

    # --- sweeps ---
    # One submit method per body form that POST /sweeps takes: a grid, explicit points, an
    # adaptive sweep.
    def submit_grid(self, name, S, R, phi, preset=None, numerics=None, priority=None,
                    max_attempts=None, replicates=None):
        """Submits the grid S x R x phi. Each axis is a number, a list of numbers or
        log_axis(lo, hi, n) / linear_axis(lo, hi, n). preset: "fast", "default" or "reference"
        (None: the server's default); numerics: further numerics keys (cells_per_unit,
        eps_end, ...) over the preset. replicates: (n, perturbation) runs each point n times,
        seeds 1..n, the particles perturbed by that fraction of their spacing (or a dict
        {"n", "perturbation"}; docs/replicates.md). Returns the created sweep (its "id",
        "counts" and "created": how many jobs are new, reused, shared or requeued)."""
        body = {"name": name, "S": _axis(S), "R": _axis(R), "phi": _axis(phi)}
        return self._submit(body, preset, numerics, priority, max_attempts, replicates)

    def submit_points(self, name, points, preset=None, numerics=None, priority=None,
                      max_attempts=None, replicates=None):
        """Submits explicit points: each {"S", "R", "phi"} or a tuple (S, R, phi). The other
        arguments are those of submit_grid."""
        body = {"name": name, "points": [_point(i, p) for i, p in enumerate(points)]}
        return self._submit(body, preset, numerics, priority, max_attempts, replicates)

    def submit_adaptive(self, name, phi, S, R, initial=None, resolution_decades=None,
                        budget=None, in_flight=None, preset=None, numerics=None, priority=None,
                        max_attempts=None, replicates=None, levels=None, budget_cpu_hours=None):
        """Submits an adaptive sweep at one phi over the box S = (min, max), R = (min, max):
        an initial log grid of initial = (points in S, points in R), refined where labels
        differ down to resolution_decades, at most budget runs in all and in_flight queued or
        running at once. What is None takes the server's default (GET /api/v1/limits,
        "adaptive": 5 x 5 points, an eighth of a decade, 200 runs). The other arguments are
        those of submit_grid. The sweep's counts grow as the server adds points
        (docs/adaptive.md). levels: numerics coarse to fine ([{"preset": "default"},
        {"cells_per_strut": 8}]) and budget_cpu_hours a budget by the cost model: the map
        then spends replicates and finer levels where its labels disagree."""
        spec = {"S": {"min": S[0], "max": S[1]}, "R": {"min": R[0], "max": R[1]}}
        if initial is not None:
            spec["initial"] = {"S": initial[0], "R": initial[1]}
        for key, value in (("resolution_decades", resolution_decades), ("budget", budget),
                           ("in_flight", in_flight), ("levels", levels),
                           ("budget_cpu_hours", budget_cpu_hours)):
            if value is not None:
                spec[key] = value
        body = {"name": name, "phi": phi, "adaptive": spec}
        return self._submit(body, preset, numerics, priority, max_attempts, replicates)

    def _submit(self, body, preset, numerics, priority, max_attempts, replicates=None):
        numerics = dict(numerics or {})
        if preset is not None:
            if "preset" in numerics and numerics["preset"] != preset:
                raise ValueError("preset %r and numerics['preset'] %r disagree"
                                 % (preset, numerics["preset"]))
            numerics["preset"] = preset
        if numerics:
            body["numerics"] = numerics
        if priority is not None:
            body["priority"] = priority
        if max_attempts is not None:
            body["max_attempts"] = max_attempts
        if replicates is not None:
            body["replicates"] = _replicates(replicates)
        return self._json("POST", "/sweeps", body, write=True)

    def sweeps(self):
        """Every sweep, newest first as the server lists them."""
        return self._all_pages("/sweeps", "sweeps", {})

    def sweep(self, sweep):
        """One sweep (a sweep or its id): state ("active", "done", "cancelled"), counts by job
        state, progress (0 to 1), the request it was made from."""
        return self._json("GET", "/sweeps/%d" % _id(sweep))

    def cancel(self, sweep):
        """Cancels the sweep's queued and running jobs that no other live sweep wants;
        returns {"id", "cancelled_jobs"}."""
        return self._json("POST", "/sweeps/%d/cancel" % _id(sweep), {}, write=True)

    def plan(self, sweep, limit=20):
        """An adaptive sweep's plan: {"state", "resolved", "runs", "lattice", "candidates_total",
        "candidates"} (docs/adaptive.md); ApiError 409 for a grid sweep."""
        return self._json("GET", "/sweeps/%d/plan" % _id(sweep), query={"limit": limit})

    def _adaptive_planning(self, s):
        # An adaptive sweep reads done for a moment between a result and the points the planner
        # adds for it; its plan says "planning" then.
        if "adaptive" not in s.get("request", {}) or s["state"] == "cancelled":
            return False
        return self.plan(s["id"], limit=0)["state"] == "planning"

    def wait(self, sweep, progress=True, timeout=None, poll=1.0):
        """Polls the sweep every `poll` seconds until no job of it is queued or running (or it
        was cancelled) and returns it as sweep() does. progress: a bar on stderr (done/total,
        failed, elapsed). timeout: seconds, after which TimeoutError; None waits for ever."""
        sweep_id = _id(sweep)
        start = time.monotonic()
        bar = Bar() if progress else None
        try:
            while True:
                s = self.sweep(sweep_id)
                elapsed = time.monotonic() - start
                if bar:
                    bar.show(s, elapsed)
                if s["state"] != "active" and not self._adaptive_planning(s):
                    return s
                if timeout is not None and elapsed >= timeout:
                    c = s["counts"]
                    raise TimeoutError("sweep %d is not finished after %g s: %d queued, %d running"
                                       % (sweep_id, timeout, c["queued"], c["running"]))
                pause = poll if timeout is None else min(poll, max(0.0, timeout - elapsed))
                time.sleep(pause)
        finally:
            if bar:
                bar.close()

    def results(self, sweep, frame=True):
        """One row per job of the sweep: the job's fields (job_id, S, R, phi, cells_per_unit,
        eps_end, state, attempts, last_error, worker, timings, ...; not the scene, see job())
        and its result's (RESULT_COLUMNS; None while the job has no result). A pandas DataFrame
        (ImportError without pandas); frame=False gives a list of dicts."""
        export = self._json("GET", "/sweeps/%d/export" % _id(sweep), query={"format": "json"})
        rows, columns = [], None
        for job in export["jobs"]:
            row = {"job_id": job["id"]}
            row.update((k, v) for k, v in job.items() if k not in ("id", "scene", "result"))
            result = job["result"] or {}
            row.update((k, result.get(k)) for k in RESULT_COLUMNS)
            rows.append(row)
            columns = columns or list(row)
        return _frame(rows, columns or ["job_id", "S", "R", "phi", "state", *RESULT_COLUMNS],
                      frame, "results()")

    def phase_map(self, phi, sweep=None, frame=True, geometry=None):
        """The runs of the phase map at one phi (of every sweep, or of one): a row per job with
        S, R, state, class, confidence, runner_up, n_reflections, band_speed_ratio, job_id,
        point_id, status, ... A pandas DataFrame (ImportError without pandas); frame=False
        gives a list of dicts. points() reads a point's replicates together. geometry: the
        runs of "pseudo1d" (the server's default), "full2d" or "pseudo1d_3d"."""
        query = {"phi": repr(float(phi)), "sweep": None if sweep is None else _id(sweep),
                 "geometry": geometry}
        points = self._json("GET", "/phase-map", query=query)["points"]
        columns = list(points[0]) if points else ["S", "R", "phi", "state", "class", "job_id"]
        return _frame(points, columns, frame, "phase_map()")

    def points(self, phi=None, sweep=None, frame=True, geometry=None):
        """The map's points: a row per point (a computation up to its seed: its replicates
        read together, docs/replicates.md) with point_id, S, R, phi, cells_per_unit, runs,
        finished, labelled, label (the majority), share, robust, p_a .. p_f (each class's
        share) and each band-speed reading as <name>_mean, <name>_sd, <name>_n. At one phi (of
        every sweep, or of one), or of one sweep at every phi (phi=None). A pandas DataFrame
        (ImportError without pandas); frame=False gives a list of dicts. geometry as in
        phase_map() (a sweep's export holds every geometry of the sweep)."""
        if phi is None:
            if sweep is None:
                raise ValueError("points(): give phi, sweep or both")
            summaries = self._json("GET", "/sweeps/%d/export" % _id(sweep),
                                   query={"format": "json"})["points"]
        else:
            query = {"phi": repr(float(phi)), "sweep": None if sweep is None else _id(sweep),
                     "geometry": geometry}
            summaries = self._json("GET", "/phase-map", query=query)["summaries"]
        rows = [_point_row(p) for p in summaries]
        return _frame(rows, POINT_COLUMNS, frame, "points()")

    def regions(self, phi, sweep=None, cells_per_unit=None, grid=None, geometry=None):
        """The classes the labelled runs predict over the map at phi, with an uncertainty per
        cell (GET /phase-map/regions): {"grid", "runs", "S": {log_min, log_max}, "R": {...},
        "classes": [one string of class letters per row of R, '.' none], "uncertainty"}."""
        query = {"phi": repr(float(phi)), "sweep": None if sweep is None else _id(sweep),
                 "cells_per_unit": cells_per_unit, "grid": grid, "geometry": geometry}
        return self._json("GET", "/phase-map/regions", query=query)

    # --- jobs and their results ---
    def jobs(self, sweep=None, state=None, phi=None):
        """Jobs (a list of dicts), filtered by sweep, state ("queued", "running", "succeeded",
        "failed", "cancelled") and phi."""
        query = {"sweep": None if sweep is None else _id(sweep), "state": state,
                 "phi": None if phi is None else repr(float(phi))}
        return self._all_pages("/jobs", "jobs", query)

    def runs(self, sort="id", limit=None, frame=True, **filters):
        """The run table (GET /jobs?format=table, docs/service.md "The run table"): a row per
        run with its columns (id, sweep, state, S, R, phi, preset, cells_per_unit,
        cells_per_strut, seed, point_id, status, class, confidence, runner_up, n_reflections,
        band_speed_ratio, human_label, label, source_database, source_job, geometry), every page
        read by its cursor. sort: a column, "-column" descending. limit: the most rows (None:
        all). filters: the table's parameters by name (sweep, point, state, phi, cells_per_unit,
        preset, geometry, label, human_label, imported, source, q, S_min, ...); cls for class; a list for
        the comma-separated ones (state=["failed", "cancelled"]); S, R, confidence,
        n_reflections, band_speed_ratio as (min, max), None for an open end. The server judges
        the values (ApiError 422 naming the parameter). A pandas DataFrame (ImportError without
        pandas); frame=False gives a list of dicts."""
        query = {"format": "table", "sort": sort}
        for name, value in filters.items():
            name = "class" if name == "cls" else name
            if name in RANGE_FILTERS and isinstance(value, (tuple, list)):
                if len(value) != 2:
                    raise ValueError("%s: expected (min, max), got %d values" % (name, len(value)))
                query[name + "_min"], query[name + "_max"] = (_query_value(v) for v in value)
            else:
                query[name] = _query_value(_id(value) if name == "sweep" else value)
        rows, columns, cursor = [], [], None
        while limit is None or len(rows) < limit:
            page_rows = PAGE_LIMIT if limit is None else min(PAGE_LIMIT, limit - len(rows))
            page = self._json("GET", "/jobs", query=dict(query, limit=page_rows, cursor=cursor))
            rows += page["rows"]
            columns = page["columns"]
            cursor = page["next"]
            if cursor is None:
                break
        return _frame(rows, columns, frame, "runs()")

    def job(self, job_id):
        """One job: its scene, state, attempts, events, and its result with the run's
        summary.json (result["summary"])."""
        return self._json("GET", "/jobs/%d" % job_id)

    def set_label(self, job_id, label, reason, by):
        """Sets a person's label (a-f) on a run with a result, with why and who (submit
        token); the classifier's stays in result["class"]. Returns the run's labels."""
        return self._json("PUT", "/jobs/%d/label" % job_id,
                          {"label": label, "reason": reason, "by": by}, write=True)

    def clear_label(self, job_id, by, reason=None):
        """Removes the person's label: the classifier's is the run's label again."""
        body = {"by": by} if reason is None else {"by": by, "reason": reason}
        return self._json("DELETE", "/jobs/%d/label" % job_id, body, write=True)

    def labels(self, job_id):
        """{"human_label", "classifier", "changes" (newest first), "total"} of one run."""
        return self._json("GET", "/jobs/%d/label" % job_id)

    def label_audit(self, job=None, limit=100, offset=0):
        """Every change of a human label, newest first: {"changes", "total", ...}."""
        return self._json("GET", "/labels/audit", query={"job": job, "limit": limit, "offset": offset})

    def export_archive(self, sweep, path, artifacts="run_page"):
        """Writes the sweep's export file (schema/sweep-export.md) that another server
        imports; returns the path. artifacts: "run_page" (every file but the particle
        snapshots) or "none" (the results and their provenance only, a few kB a run)."""
        sweep_id = sweep["id"] if isinstance(sweep, dict) else sweep
        data = self._call("GET", "/sweeps/%d/export" % sweep_id,
                          query={"format": "archive", "artifacts": artifacts})
        with open(path, "wb") as f:
            f.write(data)
        return path

    def import_archive(self, path):
        """Merges an export file into this server's database (submit token); returns the
        outcome {"sweep_id", "added", "identical", "conflicts", "changed", ...}."""
        with open(path, "rb") as f:
            body = json.loads(f.read())
        return self._json("POST", "/imports", body, write=True)

    def artifacts(self, job_id):
        """The files of the job's result bundle: [{"name", "content_type", "size", "url"}]."""
        return self._json("GET", "/jobs/%d/artifacts" % job_id)["artifacts"]

    def artifact(self, job_id, name):
        """The bytes of one file of the job's bundle (e.g. "frames.csv", "spacetime.png")."""
        return self._call("GET", "/jobs/%d/artifacts/%s" % (job_id, urllib.parse.quote(name, "")))

    def download(self, job_id, name, path=None):
        """Writes one artifact to `path` (default: `name` in the current folder; a folder:
        `name` in it) and returns the path written."""
        if path is None:
            path = name
        elif os.path.isdir(path):
            path = os.path.join(path, name)
        data = self.artifact(job_id, name)
        with open(path, "wb") as f:
            f.write(data)
        return path

    def download_bundle(self, job_id, folder):
        """Writes every artifact of the job into `folder` (made if missing), as the run wrote
        its bundle; returns the paths written."""
        os.makedirs(folder, exist_ok=True)
        return [self.download(job_id, a["name"], os.path.join(folder, a["name"]))
                for a in self.artifacts(job_id)]

    def load_npy(self, job_id, name, array=True):
        """A .npy artifact (spacetime.npy, velocity.npy, snapshot_<eps>.npy) as a numpy array
        (ImportError without numpy); array=False gives nested lists of Python numbers."""
        return npy.load(self.artifact(job_id, name), array, "load_npy()")

    def spacetime(self, job_id, array=True):
        """The space-time map [n_frames, n_rows] of the job's run (float32: the row-averaged
        plastic strain rate / (V / h0), schema/bundle-format.md); `array` as in load_npy."""
        return npy.load(self.artifact(job_id, "spacetime.npy"), array, "spacetime()")
