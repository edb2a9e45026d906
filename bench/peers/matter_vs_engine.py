"""Matter (the authors' MPM code) against compaction-run on the same scene, alternately, in one run.

Builds bench/peers/matter_driver.cpp against a Matter checkout given with --matter (Matter's
source stays there: nothing of it is copied into this repository), twice: with the flags our
engine's library is compiled with in its release build (-O3 -DNDEBUG -fno-math-errno
-fno-trapping-math -ffp-contract=off, the portable x86-64 baseline) and with -march=native
added. Then, --rounds times in alternation (the order reversed every other round):
  reference scene (pseudo-1D, phi = 0.4, 20 cells per unit cell, 2 x 2 particles per cell,
  S = 4e-3, R = 1e-5, eps 0 -> 0.008, one thread): Matter (both builds), ours with one velocity
  field (single_field), the default preset (pore_contact auto: two fields here) and one field
  with the B-spline gradient (Matter's gradient);
  large scene (40 cells per unit cell, eps 0 -> 0.002) on one and on two threads: Matter
  (portable build), ours single_field and the default preset.
Before the rounds, one untimed check that both codes simulate the same physics: Matter one frame
per simulate() call (the driver's --check) and ours with a snapshot at the end, compared
particle by particle (both place the same lattice in the same order), by kinetic energy and net
plate force per frame, by plastic activity and by the band's position.
Writes a Markdown report (--out) with the command, the machine, medians, ratios Matter / ours
and what differs between the two codes.

usage: python3 -m bench.peers.matter_vs_engine --matter SRC [--run BIN] [--rounds 3]
       [--out FILE] [--work DIR]
"""
import argparse
import concurrent.futures
import datetime
import json
import math
import os
import shlex
import statistics
import struct
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "python"))
from compaction_client import npy  # noqa: E402  (standard library only with array=False)

DRIVER = os.path.join(ROOT, "bench", "peers", "matter_driver.cpp")
# Our engine library's flags (CMake Release, and engine/CMakeLists.txt's compaction_vector_math),
# with Matter's C++17 and OpenMP.
BASE_FLAGS = ["-std=c++17", "-O3", "-DNDEBUG", "-fno-math-errno", "-fno-trapping-math",
              "-ffp-contract=off", "-fopenmp"]
NATIVE = ["-march=native"]

# The scene: S, R and phi given to both codes; h0, nu, q_y (rho = 1000) and the 34 rows are
# compaction-run's defaults (engine/include/compaction/params.hpp) and the driver's constants.
S, R, PHI, H0, NU, Q_Y, N_ROWS = 4e-3, 1e-5, 0.4, 1.0, 0.3, 250.0, 34
SCENES = {"reference": {"cells_per_unit": 20, "eps_end": 0.008},
          "large": {"cells_per_unit": 40, "eps_end": 0.002}}
OURS = {"single_field": {"pore_contact": "single_field"},
        "default": {},  # the default preset: pore_contact auto
        "single_field_bspline": {"pore_contact": "single_field", "gradient": "bspline"}}
# (scene, threads, the runs: ("matter", build) or ("ours", variant)) of each round.
CASES = [("reference", 1, [("matter", "portable"), ("matter", "native"), ("ours", "single_field"),
                           ("ours", "default"), ("ours", "single_field_bspline")]),
         ("large", 1, [("matter", "portable"), ("ours", "single_field"), ("ours", "default")]),
         ("large", 2, [("matter", "portable"), ("ours", "single_field"), ("ours", "default")])]


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown CPU"


def git_head(src):
    res = subprocess.run(["git", "-C", src, "rev-parse", "HEAD"], capture_output=True, text=True)
    return res.stdout.strip() if res.returncode == 0 else "unknown commit (not a git checkout)"


def build_matter(src, work):
    """Compiles Matter's src/simulation/*.cpp but save_data.cpp (it needs tinyply; the driver
    defines its functions as no-ops) and the driver, two files at a time, for both builds.
    Returns {build: binary} and {build: its flags}."""
    sim = os.path.join(src, "src", "simulation")
    sources = sorted(os.path.join(sim, f) for f in os.listdir(sim)
                     if f.endswith(".cpp") and f != "save_data.cpp") + [DRIVER]
    include = ["-I", os.path.join(src, "src"), "-I", "/usr/include/eigen3",
               '-DSRC_DIR="%s"' % os.path.join(src, "src")]  # simulation.cpp names it
    builds = {"portable": BASE_FLAGS, "native": BASE_FLAGS + NATIVE}
    jobs = []
    for name, flags in builds.items():
        os.makedirs(os.path.join(work, name), exist_ok=True)
        for s in sources:
            obj = os.path.join(work, name, os.path.basename(s) + ".o")
            jobs.append((name, obj, ["g++"] + flags + include + ["-c", s, "-o", obj]))

    def compile_one(job):
        res = subprocess.run(job[2], capture_output=True, text=True)
        if res.returncode != 0:
            raise RuntimeError("compiling failed: %s\n%s" % (shlex.join(job[2]), res.stderr))
        return job

    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        done = list(pool.map(compile_one, jobs))
    binaries = {}
    for name, flags in builds.items():
        out = os.path.join(work, name, "matter_driver")
        objs = [obj for n, obj, _ in done if n == name]
        subprocess.run(["g++"] + flags + objs + ["-o", out], check=True)
        binaries[name] = out
    return binaries, {name: " ".join(flags) for name, flags in builds.items()}


def matter_args(scene, threads):
    sc = SCENES[scene]
    return ["--S", str(S), "--R", str(R), "--phi", str(PHI),
            "--cells-per-unit", str(sc["cells_per_unit"]), "--eps-end", str(sc["eps_end"]),
            "--threads", str(threads)]


def run_matter(binary, scene, threads, extra=()):
    res = subprocess.run([binary] + matter_args(scene, threads) + list(extra),
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if res.returncode != 0:
        raise RuntimeError("Matter failed (%d): %s" % (res.returncode, res.stderr[-2000:]))
    return json.loads(res.stdout.strip().splitlines()[-1])


def ours_flags(scene, variant, threads):
    sc = SCENES[scene]
    flags = {"S": S, "R": R, "phi": PHI, "cells_per_unit": sc["cells_per_unit"],
             "eps_end": sc["eps_end"], "threads": threads, "snapshot_eps": "", "movie_d_eps": 0,
             **OURS[variant]}
    return [arg for k, v in flags.items() for arg in ("--" + k.replace("_", "-"), str(v))]


def run_ours(binary, scene, variant, threads, out, extra=()):
    cmd = [binary, "--progress", "none", "--out", out] + ours_flags(scene, variant, threads)
    subprocess.run(cmd + list(extra), check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    with open(os.path.join(out, "summary.json")) as f:
        s = json.load(f)
    return {"steps": s["steps"], "n_particles": s["n_particles"],
            "wall_seconds": s["wall_seconds"], "ns_per_particle_step": s["ns_per_particle_step"],
            "pore_contact": s["grid"]["pore_contact"]}


# ---------------------------------------------------------------------------------------------
# The physics check.

def read_csv(path):
    with open(path) as f:
        head = f.readline().strip().split(",")
        return [dict(zip(head, map(float, line.split(",")))) for line in f if line.strip()]


def lattice0(cells_per_unit):
    """The initial positions of both codes' particles, in their order (matter_driver.cpp's
    column_particles, compaction-run's place_particles)."""
    per_unit = cells_per_unit * 2
    L = H0 / N_ROWS
    spacing = L / per_unit
    side = min(max(int(math.floor(L * math.sqrt(1 - PHI) / spacing + 0.5)), 0), per_unit - 1)
    first = (per_unit - side) // 2
    pts = []
    for j in range(N_ROWS * per_unit):
        ly = j % per_unit
        for i in range(per_unit):
            if first <= ly < first + side and first <= i < first + side:
                continue
            pts.append(((i + 0.5) * spacing, (j + 0.5) * spacing))
    return pts


def front_height(velocity, dx):
    """The height (in unit cells) of the lowest row of dx whose mean vertical velocity is at least
    half the plate's (v_y / V <= -0.5): where the zone that moves with the plate starts."""
    for r, v in enumerate(velocity):
        if v <= -0.5:
            return r * dx / (H0 / N_ROWS)
    return float("nan")


def particles_summary(xy, ep, J, x0, dx, L):
    disp = [math.hypot(x - a, y - b) / dx for (x, y), (a, b) in zip(xy, x0)]
    plastic = sum(1 for e in ep if e > 0)
    return {"rms_disp": math.sqrt(sum(d * d for d in disp) / len(disp)), "max_disp": max(disp),
            "plastic": plastic, "ep_sum": sum(ep), "J_min": min(J), "J_mean": sum(J) / len(J)}


def physics_check(matter_bin, run_bin, work):
    scene, eps_end = "reference", SCENES["reference"]["eps_end"]
    cells = SCENES["reference"]["cells_per_unit"]
    L = H0 / N_ROWS
    dx = L / cells
    x0 = lattice0(cells)
    mdir = os.path.join(work, "check-matter")
    os.makedirs(mdir, exist_ok=True)
    m_info = run_matter(matter_bin, scene, 1, ["--check", mdir])
    with open(os.path.join(mdir, "particles.bin"), "rb") as f:
        raw = f.read()
    rec = [struct.unpack_from("<4d", raw, 32 * k) for k in range(len(raw) // 32)]
    m = {"xy": [(r[0], r[1]) for r in rec], "ep": [r[2] for r in rec], "J": [r[3] for r in rec],
         "frames": read_csv(os.path.join(mdir, "frames.csv"))}
    with open(os.path.join(mdir, "velocity.csv")) as f:
        m["velocity"] = [float(v) for v in f.read().split()]
    ours = {}
    for variant in ("single_field", "default", "single_field_bspline"):
        out = os.path.join(work, "check-" + variant)
        run_ours(run_bin, scene, variant, 1, out, ["--snapshot-eps", str(eps_end)])
        with open(os.path.join(out, "summary.json")) as f:
            snap = json.load(f)["snapshots"]
        name = snap[-1]["file"] if isinstance(snap[-1], dict) else snap[-1]
        with open(os.path.join(out, name), "rb") as f:
            rows = npy.load(f.read(), array=False)
        with open(os.path.join(out, "velocity.npy"), "rb") as f:
            vel = npy.load(f.read(), array=False)
        ours[variant] = {"xy": [(r[0], r[1]) for r in rows], "ep": [r[3] for r in rows],
                         "J": [r[4] for r in rows], "velocity": vel[-1],
                         "frames": read_csv(os.path.join(out, "frames.csv"))}
    if any(len(o["xy"]) != len(m["xy"]) for o in ours.values()) or len(m["xy"]) != len(x0):
        raise RuntimeError("the codes have different particle counts")
    lines = ["| quantity | Matter | " + " | ".join("ours " + v for v in ours) + " |",
             "|---|---|" + "---|" * len(ours)]
    sm = particles_summary(m["xy"], m["ep"], m["J"], x0, dx, L)
    so = {v: particles_summary(o["xy"], o["ep"], o["J"], x0, dx, L) for v, o in ours.items()}

    def row(label, fmt, mv, ov):
        lines.append("| %s | %s | %s |" % (label, fmt % mv, " | ".join(fmt % ov[v] for v in ours)))

    row("particle displacement since t = 0, RMS (dx)", "%.3f", sm["rms_disp"],
        {v: s["rms_disp"] for v, s in so.items()})
    row("particle displacement since t = 0, largest (dx)", "%.2f", sm["max_disp"],
        {v: s["max_disp"] for v, s in so.items()})

    def diff(o):
        d = []
        for (xa, ya), (xb, yb) in zip(m["xy"], o["xy"]):
            ddx = (xa - xb + 0.5 * L) % L - 0.5 * L  # periodic in x
            d.append(math.hypot(ddx, ya - yb) / dx)
        return d

    diffs = {v: diff(o) for v, o in ours.items()}
    lines.append("| position against Matter's, RMS (dx) | - | %s |" % " | ".join(
        "%.2g" % math.sqrt(sum(x * x for x in d) / len(d)) for d in diffs.values()))
    lines.append("| position against Matter's, largest (dx) | - | %s |" % " | ".join(
        "%.2g" % max(d) for d in diffs.values()))
    row("particles that yielded", "%d", sm["plastic"], {v: s["plastic"] for v, s in so.items()})
    row("sum of accumulated plastic strain", "%.1f", sm["ep_sum"],
        {v: s["ep_sum"] for v, s in so.items()})
    row("J = det F, smallest", "%.4f", sm["J_min"], {v: s["J_min"] for v, s in so.items()})
    row("front: lowest row moving at >= V/2 (unit cells)", "%.2f", front_height(m["velocity"], dx),
        {v: front_height(o["velocity"], dx) for v, o in ours.items()})
    for k, f in enumerate(m["frames"]):
        ke = {v: o["frames"][k]["kinetic_energy"] for v, o in ours.items()}
        row("kinetic energy at eps = %.3f (mJ/m)" % f["eps"], "%.3f", 1e3 * f["kinetic_energy"],
            {v: 1e3 * x for v, x in ke.items()})
    for k, f in enumerate(m["frames"]):
        net = {v: o["frames"][k]["sigma_top"] - o["frames"][k]["sigma_bottom"]
               for v, o in ours.items()}
        row("sigma_top - sigma_bottom / q_y, frame to eps = %.3f" % f["eps"], "%.3f",
            f["sigma_top_minus_bottom"] / Q_Y, {v: x / Q_Y for v, x in net.items()})
    for k, f in enumerate(m["frames"]):
        top = {v: o["frames"][k]["sigma_top"] / Q_Y for v, o in ours.items()}
        lines.append("| ours' sigma_top / q_y, frame to eps = %.3f | (not measured) | %s |" % (
            f["eps"], " | ".join("%.3f" % top[v] for v in ours)))
    return lines, m_info


# ---------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--matter", required=True, help="a checkout of Matter (its src/ is read)")
    ap.add_argument("--run", default=os.path.join(ROOT, "build", "bin", "compaction-run"),
                    help="our compaction-run [build/bin/compaction-run]")
    ap.add_argument("--rounds", type=int, default=3, help="alternating rounds (default 3)")
    ap.add_argument("--out", help="write the report here as well as to stdout")
    ap.add_argument("--work", help="build and run here [a temporary folder, removed]")
    a = ap.parse_args()
    if a.rounds < 1:
        ap.error("--rounds must be at least 1")
    if not os.path.isfile(os.path.join(a.matter, "src", "simulation", "simulation.hpp")):
        ap.error("--matter: %s has no src/simulation/simulation.hpp" % a.matter)
    if not os.access(a.run, os.X_OK):
        ap.error("--run: %s is not an executable" % a.run)
    command = "python3 -m bench.peers.matter_vs_engine " + shlex.join(sys.argv[1:])
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%S UTC")
    load = os.getloadavg()
    version = subprocess.run([a.run, "--version"], capture_output=True, text=True).stdout.strip()
    with tempfile.TemporaryDirectory() as tmp:
        work = a.work or tmp
        print("building Matter's driver ...", file=sys.stderr, flush=True)
        binaries, flags = build_matter(a.matter, work)
        print("physics check ...", file=sys.stderr, flush=True)
        check_lines, check_info = physics_check(binaries["portable"], a.run, work)
        rows = {}  # (scene, threads, code, variant) -> [result per round]
        for r in range(a.rounds):
            for scene, threads, runs_ in CASES:
                order = runs_ if r % 2 == 0 else list(reversed(runs_))
                for code, variant in order:
                    if code == "matter":
                        res = run_matter(binaries[variant], scene, threads)
                    else:
                        res = run_ours(a.run, scene, variant, threads,
                                       os.path.join(work, "%s-%s-%d" % (scene, variant, threads)))
                    rows.setdefault((scene, threads, code, variant), []).append(res)
                    print("round %d: %s, %d thread(s), %s %s: %.1f ns, %.2f s" % (
                        r + 1, scene, threads, code, variant, res["ns_per_particle_step"],
                        res["wall_seconds"]), file=sys.stderr, flush=True)
    load = load + os.getloadavg()  # at the start and at the end
    text = report(a, command, started, load, version, flags, rows, check_lines, check_info)
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text)


def med(rs, key):
    return statistics.median(r[key] for r in rs)


def report(a, command, started, load, version, flags, rows, check_lines, check_info):
    L = ["# Matter against our engine on the same scene", ""]
    L += ["Made by `%s`, started %s, on %s (%d CPUs; load average %.2f %.2f %.2f at the start "
          "and %.2f %.2f %.2f at the end: the machine is shared with other work, so only ratios "
          "measured in one session mean anything). Matter: %s "
          "(%s). Ours: `%s` (`%s`), its release build." % (
              command, started, cpu_model(), os.cpu_count(), *load, a.matter,
              git_head(a.matter), a.run, version), ""]
    L += ["Builds. Ours: CMake Release, the engine library compiled with `-O3 -DNDEBUG "
          "-fno-math-errno -fno-trapping-math -ffp-contract=off` for the portable x86-64 "
          "baseline, with an AVX2 and an AVX-512 copy of the particle loops chosen at run time "
          "(on this processor the AVX-512 copy; engine/src/simd_dispatch.hpp). Matter: "
          "bench/peers/matter_driver.cpp with Matter's src/simulation/*.cpp but save_data.cpp, "
          "`g++ %s`: the same flags (Matter's own CMake Release build has `-O3 -DNDEBUG`; the "
          "three others change none of its results). Matter has no run-time dispatch, so its "
          "loops get the baseline's SSE2; a second build, `g++ %s`, is timed on the reference "
          "scene only. g++ %s, Debian's Eigen %s." % (
              flags["portable"], flags["native"], gcc_version(), eigen_version()), ""]
    L += ["Scenes: pseudo-1D column, phi = 0.4, S = 4e-3, R = 1e-5, 2 x 2 particles per cell, "
          "plates bonded and frictionless. Reference: 20 cells per unit cell, eps 0 -> 0.008; "
          "large: 40 cells per unit cell, eps 0 -> 0.002. Medians of %d rounds in alternation "
          "(the order reversed every other round); wall time of the time-stepping loop (ours: "
          "summary.json's `wall_seconds`; Matter: its `simulate()` call, which holds nothing but "
          "the loop and a few lines of printing)." % a.rounds, ""]
    L += ["## Timings", ""]
    L += ["ns / particle-step is each code's wall time over its own steps and its own particles "
          "(Matter: without its ghost copies; the column `with ghosts` counts them too). "
          "`per our step and particle` divides Matter's wall time by our single_field run's steps "
          "and particles on the same scene instead: both codes simulate the same imposed strain, "
          "so that column over ours is the ratio of wall times for the same simulated time.", ""]
    L += ["| scene | threads | code | particles (with ghosts) | steps | wall (s) "
          "| ns / particle-step | with ghosts | per our step and particle |",
          "|---|---|---|---|---|---|---|---|---|"]
    for scene, threads, runs_ in CASES:
        ref = rows[(scene, threads, "ours", "single_field")]
        ref_ps = ref[0]["steps"] * ref[0]["n_particles"]
        for code, variant in runs_:
            rs = rows[(scene, threads, code, variant)]
            wall = med(rs, "wall_seconds")
            if code == "matter":
                name = "Matter" + (" (-march=native)" if variant == "native" else "")
                parts = "%d (%d)" % (rs[0]["n_particles"], rs[0]["n_with_ghosts"])
                ghosts = "%.1f" % med(rs, "ns_per_particle_step_with_ghosts")
            else:
                name = "ours, %s (%s)" % (variant.replace("_bspline", " + B-spline gradient"),
                                          rs[0]["pore_contact"])
                parts, ghosts = "%d" % rs[0]["n_particles"], "-"
            L.append("| %s | %d | %s | %s | %d | %.2f | %.1f | %s | %.1f |" % (
                scene, threads, name, parts, rs[0]["steps"], wall, med(rs, "ns_per_particle_step"),
                ghosts, 1e9 * wall / ref_ps))
    L += ["", "## Ratios Matter / ours", ""]
    L += ["Wall time over wall time for the same scene and imposed strain (medians; in brackets "
          "the per-round ratios), and the ratio of ns per particle-step, each per its own steps "
          "and particles (Matter without ghosts).", ""]
    L += ["| scene | threads | against | wall-time ratio (per round) | ns / particle-step ratio |",
          "|---|---|---|---|---|"]
    for scene, threads, runs_ in CASES:
        mrs = rows[(scene, threads, "matter", "portable")]
        for code, variant in runs_:
            if code != "ours":
                continue
            ors = rows[(scene, threads, "ours", variant)]
            per_round = [m["wall_seconds"] / o["wall_seconds"] for m, o in zip(mrs, ors)]
            L.append("| %s | %d | ours %s | **%.1f** (%s) | %.1f |" % (
                scene, threads, variant, med(mrs, "wall_seconds") / med(ors, "wall_seconds"),
                ", ".join("%.1f" % x for x in per_round),
                med(mrs, "ns_per_particle_step") / med(ors, "ns_per_particle_step")))
    nat = rows[("reference", 1, "matter", "native")]
    por = rows[("reference", 1, "matter", "portable")]
    L += ["", "Matter built with -march=native over its portable build, reference scene: %.2f "
          "(wall time; above 1: slower)." % (med(nat, "wall_seconds") / med(por, "wall_seconds"))]
    m1, m2 = rows[("large", 1, "matter", "portable")], rows[("large", 2, "matter", "portable")]
    o1, o2 = rows[("large", 1, "ours", "single_field")], rows[("large", 2, "ours", "single_field")]
    d1, d2 = rows[("large", 1, "ours", "default")], rows[("large", 2, "ours", "default")]
    L += ["", "Two threads over one on the large scene (one thread's wall time over two threads'): "
          "Matter %.2f, ours single_field %.2f, ours default %.2f." % (
              med(m1, "wall_seconds") / med(m2, "wall_seconds"),
              med(o1, "wall_seconds") / med(o2, "wall_seconds"),
              med(d1, "wall_seconds") / med(d2, "wall_seconds"))]
    L += ["", "## Same physics?", ""]
    L += ["One untimed run of each on the reference scene to eps = 0.008 (Matter's portable build, "
          "one `simulate()` call per frame so that the driver can read the particles between "
          "frames: %d steps; in its last step it projected %s particles onto the yield "
          "surface). Both codes start from the same particles in the same order, so they are "
          "compared particle by particle. Ours does not store momentum: its plate "
          "stresses come from frames.csv (the reaction impulses on the constrained nodes); "
          "Matter measures no plate force, so its net plate force per width is the loss of "
          "the particles' vertical momentum per frame (no gravity: the plates are the only "
          "external forces, so this is sigma_top - sigma_bottom)." % (
              check_info["steps"], check_info["last_proj"].replace("Proj: ", "").replace(
                  " / ", " of ")), ""]
    L += check_lines
    L += ["", "## What differs", ""]
    L += what_differs(rows)
    return "\n".join(L) + "\n"


def eigen_version():
    try:
        with open("/usr/include/eigen3/Eigen/src/Core/util/Macros.h") as f:
            text = f.read()
    except OSError:
        return "(version unknown)"
    parts = []
    for key in ("EIGEN_WORLD_VERSION", "EIGEN_MAJOR_VERSION", "EIGEN_MINOR_VERSION"):
        i = text.find("#define " + key)
        parts.append(text[i:].split()[2] if i >= 0 else "?")
    return ".".join(parts)


def gcc_version():
    res = subprocess.run(["g++", "-dumpfullversion"], capture_output=True, text=True)
    return res.stdout.strip() or "unknown"


def what_differs(rows):
    mref = rows[("reference", 1, "matter", "portable")][0]
    mlarge = rows[("large", 1, "matter", "portable")][0]
    oref = rows[("reference", 1, "ours", "single_field")][0]
    olarge = rows[("large", 1, "ours", "single_field")][0]
    c_ratio = math.sqrt((1 - NU) / ((1 + NU) * (1 - 2 * NU)))  # c_P / sqrt(E / rho)
    return [
        "- **Periodicity.** Matter copies the particles within 4 dx of either side of the "
        "periodic width as ghosts before P2G (and removes them before G2P), on a grid 11 columns "
        "wider than the period: %d ghosts on %d particles (+%.0f %%) on the reference scene, %d on "
        "%d (+%.0f %%) on the large one, every step. Ours wraps the node index of each stencil "
        "column (the grid is the period, 20 or 40 columns) and processes each particle once."
        % (mref["n_ghosts_last_step"], mref["n_particles"],
           100 * mref["n_ghosts_last_step"] / mref["n_particles"], mlarge["n_ghosts_last_step"],
           mlarge["n_particles"], 100 * mlarge["n_ghosts_last_step"] / mlarge["n_particles"]),
        "- **Stencil.** Matter loops over 4 x 4 nodes per particle in P2G and G2P (`i_base` to "
        "`i_base + 3`, valid for its cubic splines too); with quadratic B-splines one row and one "
        "column of them have zero weight (P2G skips them by a weight test, G2P multiplies by "
        "zero). Ours visits the 3 x 3 nodes of the quadratic stencil.",
        "- **Yield convention.** Matter's q = q_prefac ||dev tau|| defaults to q_prefac = "
        "sqrt(1/2); the driver sets sqrt(3/2), the paper's sqrt(3/2 s:s) that ours uses (the "
        "default would yield at about half the strain). Matter's deviator is the 2D one at "
        "dim = 2, as ours.",
        "- **Time step.** Matter: min(cfl dx / v_max, cfl_elastic dx / sqrt(E/rho)), default "
        "cfl_elastic = 0.5, i.e. 0.5 dx / sqrt(E/rho) = %.2f dx / c_P; ours: cfl dx / (c_P + "
        "v_max) with cfl = 0.5. The driver sets cfl_elastic = 0.5 sqrt(E/rho) / c_P = %.3f, "
        "so the steps differ only by v_max in our denominator: %d steps against our %d on the "
        "reference scene, %d against %d on the large one. With Matter's default it would take "
        "%.0f %% fewer steps, each cost per step unchanged; the `per our step and particle` "
        "column and the wall-time ratios compare the same simulated time either way."
        % (0.5 * c_ratio, 0.5 / c_ratio, mref["steps"], oref["steps"], mlarge["steps"],
           olarge["steps"], 100 * (1 - 1 / c_ratio)),
        "- **Transfers.** Both pure APIC with quadratic B-splines (Matter's flip_ratio < -1; its "
        "P2G adds the affine term B (x_i - x_p) 4 / dx^2). Matter's force and velocity gradient "
        "use the B-spline weight gradients; ours by default the MLS form (the affine matrix "
        "C), and `--gradient bspline` the same gradients as Matter (the row `single_field + "
        "B-spline gradient`).",
        "- **Plates.** Matter's SlipStick plates test a node's predicted position x_i + dt v_i "
        "against the plate (Matter's boundaryCollision), ours the node's position (y <= 0, "
        "y >= h0 - V t): a node on the plate's line that moves away from it is free in Matter and "
        "held in ours. Matter's plates measure no force.",
        "- **Constitutive update.** The same model (Hencky strain, plane-strain Lame constants, "
        "radial return on the 2D deviator of the principal Hencky strains). Matter takes a "
        "JacobiSVD of Fe per particle and step in double (Eigen), clamps singular values at "
        "1e-4 and keeps the Kirchhoff stress as a full matrix; ours uses a closed form for the "
        "2 x 2 case. Both keep F in double.",
        "- **Grid.** Matter zeroes a grid of the whole fixed domain (the period plus 11 "
        "columns, the column's height plus 7 rows) every step, and its P2G allocates a private "
        "copy of the grid's mass, velocity, force and friction per thread (on one thread too) and "
        "adds it to the grid under a critical section. Ours has one grid of the period; with "
        "threads each scatters into the grid where the rows are its own and into scratch "
        "arrays elsewhere (engine/src/p2g.cpp, scatter_rows.hpp).",
        "- **What else the loop does.** Ours records its diagnostics every step (plate "
        "impulses, the space-time map's rows, the stability checks) inside the timed loop; "
        "Matter prints five lines per step (the driver's filter counts them; a few microseconds "
        "a step) and computes nothing else.",
        "- **Two threads on Matter.** Its PBCAddParticles pushes the ghost copies from inside an "
        "OpenMP loop (under a critical section) while other threads read the same vectors; the "
        "driver reserves their capacity so that no push_back reallocates. Nothing else of "
        "Matter is changed.",
    ]


if __name__ == "__main__":
    main()
