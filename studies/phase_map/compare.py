"""The paper's statements about its Fig. 2 (Blatny et al. 2022), measured on a map's runs.

fig2.py calls `comparison(jobs, phi)` and appends what it returns to fig2.md; studies/phase_map/README.md
puts each number beside the sentence of the paper it tests. Every number is computed here from
the runs (their label, confidence, N_r and c_b/V); nothing is a fitted or chosen value.

A job is a dict as fig2.job_of makes it: S, R, label (the one that counts), confidence,
n_reflections, c_b.

A column is the runs of one S, ordered by R. Boundaries are read upwards from a column's lowest
run, because that is how the paper orders its classes at fixed S: (e) at the lowest R of high S,
then (a), then (b) by a growing number of reflections, and (f) above R_crit.
"""
import math
from collections import defaultdict

from studies.lib import examples
from studies.lib.cells import fmt
from studies.lib.spread import line_fit


def columns(jobs):
    """{S: [jobs ordered by R]} of the labelled runs."""
    by_s = defaultdict(list)
    for j in jobs:
        if j["label"]:
            by_s[j["S"]].append(j)
    return {S: sorted(col, key=lambda j: j["R"]) for S, col in sorted(by_s.items())}


def inertia(j):
    """R/S^2 = q_y / (rho V^2): the yield stress over the inertia stress (the paper's Fig. 3)."""
    return j["R"] / j["S"] ** 2


def bottom_block(col, label, start=0):
    """The index just past the run of `label` from col[start] upwards (start if col[start] is not
    `label`)."""
    i = start
    while i < len(col) and col[i]["label"] == label:
        i += 1
    return i


def brackets(cols, below, above, skip=()):
    """Per column, the last run of the block of `below` at the bottom (after a bottom block of each
    class in `skip`) and the run just above it, when that one is `above`: [(S, lo, hi)]."""
    found = []
    for S, col in cols.items():
        i = 0
        for k in skip:
            i = bottom_block(col, k, i)
        end = bottom_block(col, below, i)
        if end > i and end < len(col) and col[end]["label"] == above:
            found.append((S, col[end - 1], col[end]))
    return found


def common_interval(pairs):
    """The interval of R/S^2 inside every bracket, or None: a line of constant R/S^2 through every
    column's boundary exists when this is not None."""
    lo = max(inertia(a) for _, a, _ in pairs)
    hi = min(inertia(b) for _, _, b in pairs)
    return (lo, hi) if lo < hi else None


def percentile(values, q):
    """The q-quantile (0..1) by linear interpolation between order statistics."""
    v = sorted(values)
    x = q * (len(v) - 1)
    k = int(math.floor(x))
    return v[k] if k + 1 >= len(v) else v[k] + (x - k) * (v[k + 1] - v[k])


def ranks(values):
    """Ranks 1..n, ties sharing their mean rank."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    r = [0.0] * len(values)
    i = 0
    while i < len(order):
        k = i
        while k + 1 < len(order) and values[order[k + 1]] == values[order[i]]:
            k += 1
        for m in range(i, k + 1):
            r[order[m]] = (i + k) / 2 + 1
        i = k + 1
    return r


def pearson(x, y):
    n = len(x)
    mx, my = sum(x) / n, sum(y) / n
    sxy = sum((a - mx) * (b - my) for a, b in zip(x, y))
    sxx = sum((a - mx) ** 2 for a in x)
    syy = sum((b - my) ** 2 for b in y)
    return sxy / math.sqrt(sxx * syy) if sxx > 0 and syy > 0 else None  # undefined if constant


def bracket_rows(pairs):
    rows = ["| S | last (%s) at R | next: R, label | R/S^2 between |" % pairs[0][1]["label"],
            "|---|---|---|---|"]
    for S, a, b in pairs:
        rows.append("| %s | %s | %s, (%s) | %s and %s |" % (fmt(S), fmt(a["R"]), fmt(b["R"]),
                                                              b["label"], fmt(inertia(a), 2),
                                                              fmt(inertia(b), 2)))
    return rows


def longest_common(pairs):
    """The longest stretch of neighbouring columns (pairs ordered by S) through whose brackets one
    R/S^2 passes: (first, last, interval)."""
    best = None
    for i in range(len(pairs)):
        k = i
        while k + 1 < len(pairs) and common_interval(pairs[i:k + 2]):
            k += 1
        if best is None or k - i > best[1] - best[0]:
            best = (i, k, common_interval(pairs[i:k + 1]))
    return best


def interval_line(pairs, what):
    mids = [math.sqrt(inertia(a) * inertia(b)) for _, a, b in pairs]
    text = ("%s, %d columns: the geometric middles of the brackets lie at R/S^2 = %s to %s; "
            % (what, len(pairs), fmt(min(mids), 2), fmt(max(mids), 2)))
    first, last, common = longest_common(pairs)
    if last - first + 1 == len(pairs):
        return text + ("one R/S^2 passes through every bracket: %s to %s." %
                       (fmt(common[0], 2), fmt(common[1], 2)))
    return text + ("one R/S^2 passes through the brackets of %d neighbouring columns, S = %s to "
                   "%s: %s to %s." % (last - first + 1, fmt(pairs[first][0], 2),
                                      fmt(pairs[last][0], 2), fmt(common[0], 2),
                                      fmt(common[1], 2)))


def comparison(jobs, phi, r_crit):
    """Markdown lines: the paper's statements about Fig. 2 and what the runs measure."""
    cols = columns(jobs)
    out = ["## The resolution reached, per column", "",
           "Upwards in R: the label changes between neighbouring runs and the widest gap in R "
           "across one (a boundary known to that width), with the column's median run time:", "",
           "| S | runs | label changes | widest gap across a change (decades of R) | "
           "median run time (s) |", "|---|---|---|---|---|"]
    for S, col in cols.items():
        gaps = [math.log10(col[i + 1]["R"] / col[i]["R"]) for i in range(len(col) - 1)
                if col[i]["label"] != col[i + 1]["label"]]
        walls = [j["wall"] for j in col if j.get("wall")]
        out.append("| %s | %d | %d | %s | %s |" % (fmt(S), len(col), len(gaps),
                                                   fmt(max(gaps), 2) if gaps else "-",
                                                   "%.0f" % percentile(walls, 0.5) if walls else "-"))
    pairs = [(a, b) for col in cols.values() for a, b in zip(col, col[1:]) if a["label"] != b["label"]]
    near = sum(1 for a, b in pairs if a["runner_up"] == b["label"] or b["runner_up"] == a["label"])
    out += ["", "At %d of the %d label changes, the runner-up of one of the two runs is the other's "
            "label (the classifier saw both classes there)." % (near, len(pairs))]
    out += ["", "## The paper's statements, measured on the runs (studies/phase_map/compare.py)", ""]

    # (e) at low R and high S; its upper edge.
    ea = brackets(cols, "e", "a")
    e_cols = [S for S, col in cols.items() if col[0]["label"] == "e"]
    if e_cols:
        upward = all(S in e_cols for S in cols if S >= min(e_cols))
        out += ["**(e) at low R and high S.** Columns whose lowest run is (e): %d of %d, S = %s to "
                "%s%s." % (len(e_cols), len(cols), fmt(min(e_cols), 2), fmt(max(e_cols), 2),
                           ", every column from the first up" if upward else
                           " (not every column between them)"), ""]
    if ea:
        out += bracket_rows(ea) + ["", interval_line(ea, "The (e)/(a) boundary"), ""]

    # (a)/(b): the first reflecting band above the bottom (a) block.
    ab = brackets(cols, "a", "b", skip=("e",))
    if ab:
        out += ["**(a) below (b).** The (a)/(b) boundary upwards in R, past the bottom (e) block:", ""]
        out += bracket_rows(ab) + ["", interval_line(ab, "The (a)/(b) boundary"), ""]

    # (a): c_b/V = 1/(1 - phi) for a non-reflecting band. A band that leaves solid fraction
    # phi_f <= 1 behind it and runs into material at rest and at phi moves at
    # c_b/V = 1/(1 - phi/phi_f) >= 1/(1 - phi) (the paper's mass balance): the same value is the
    # floor of every band's speed; a slower band runs into material that already compacts.
    floor = 1 / (1 - phi)
    for name, sel in (("(a)", lambda j: j["label"] == "a"),
                      ("(a) with N_r = 0", lambda j: j["label"] == "a" and j["n_reflections"] == 0)):
        v = [j["c_b"] for j in jobs if sel(j) and j["c_b"] is not None]
        if v:
            within = sum(1 for x in v if abs(x / floor - 1) <= 0.05)
            out.append("**c_b/V of %s**, %d runs, against 1/(1 - phi) = %s: median %s, 10 to 90 %% "
                       "%s to %s; within 5 %%: %d (%.0f %%)."
                       % (name, len(v), fmt(floor, 3), fmt(percentile(v, 0.5), 3),
                          fmt(percentile(v, 0.1), 3), fmt(percentile(v, 0.9), 3), within,
                          100.0 * within / len(v)))
    out.append("")

    # (b): N_r and c_b/V grow with R/S^2 (the paper's Figs. 2 and 3).
    b = [j for j in jobs if j["label"] == "b" and j["n_reflections"] is not None]
    bc = [j for j in b if j["c_b"] is not None and j["c_b"] > 0]
    if len(b) >= 3:
        rho = pearson(ranks([inertia(j) for j in b]), ranks([j["n_reflections"] for j in b]))
        out.append("**(b) by N_r.** %d runs (b): Spearman rank correlation of N_r with R/S^2: %s."
                   % (len(b), fmt(rho, 2)))
    for name, sel in (("with a band speed", lambda j: True),
                      ("at or above the mass balance's floor 1/(1 - phi)",
                       lambda j: j["c_b"] >= floor)):
        pts = [j for j in bc if sel(j)]
        if len(pts) >= 3:
            x = [math.log10(inertia(j)) for j in pts]
            y = [math.log10(j["c_b"]) for j in pts]
            out.append("c_b/V of the %d (b) %s, against R/S^2, log-log: slope %s, correlation %s."
                       % (len(pts), name, fmt(line_fit(x, y)[0], 2), fmt(pearson(x, y), 2)))
    slow = [j for j in jobs if j["label"] in ("a", "b") and j["c_b"] is not None
            and j["c_b"] < 0.95 * floor]
    out.append("Runs (a) or (b) whose band is more than 5 %% below that floor: %d (%s)."
               % (len(slow), ", ".join("(%s) S %s R %s: %s" % (j["label"], fmt(j["S"], 2),
                                                               fmt(j["R"], 2), fmt(j["c_b"], 3))
                                      for j in sorted(slow, key=lambda j: (j["S"], j["R"])))))
    by_nr = defaultdict(list)
    for j in jobs:
        if j["label"] in ("a", "b") and j["c_b"] is not None and j["n_reflections"] is not None:
            by_nr[min(j["n_reflections"], 4)].append(j["c_b"])
    if by_nr:
        out += ["", "| N_r of (a) and (b) | runs | median c_b/V |", "|---|---|---|"]
        for n in sorted(by_nr):
            out.append("| %s | %d | %s |" % ("4 or more" if n == 4 else n, len(by_nr[n]),
                                            fmt(percentile(by_nr[n], 0.5), 3)))
    out.append("")

    # (f) above R_crit.
    out += ["**(f) above R_crit** (the paper: about 0.05; pi^2 a^2 / 12 = %s). Per column, the "
            "lowest R of the (f) block at the top and the run below it:" % fmt(r_crit, 2), "",
            "| S | top (f) from R | the run below: R, label | (f) below R_crit |", "|---|---|---|---|"]
    for S, col in cols.items():
        i = len(col)
        while i > 0 and col[i - 1]["label"] == "f":
            i -= 1
        top = fmt(col[i]["R"]) if i < len(col) else "none"
        below = ("%s, (%s)" % (fmt(col[i - 1]["R"]), col[i - 1]["label"])) if i > 0 else "-"
        low_f = [fmt(j["R"]) for j in col if j["label"] == "f" and j["R"] < r_crit]
        out.append("| %s | %s | %s | %s |" % (fmt(S), top, below, ", ".join(low_f) or "-"))
    high = [j for j in jobs if j["label"] and j["R"] >= r_crit]
    low = [j for j in jobs if j["label"] and j["R"] < r_crit]
    out += ["", "Runs at R >= R_crit labelled (f): %d of %d; runs below R_crit labelled (f): %d of %d."
            % (sum(1 for j in high if j["label"] == "f"), len(high),
               sum(1 for j in low if j["label"] == "f"), len(low)), ""]

    # (c) near its example; (d) at low plate speed.
    Sc, Rc = examples.EXAMPLES["c"]
    cs = sorted((j for j in jobs if j["label"] == "c"),
                key=lambda j: math.hypot(math.log10(j["S"] / Sc), math.log10(j["R"] / Rc)))
    out.append("**(c)**, %d runs, nearest to the example (S = %g, R = %g) first: %s."
               % (len(cs), Sc, Rc, "none" if not cs else "; ".join(
                   "S %s R %s (%s, %s decade)" % (fmt(j["S"], 2), fmt(j["R"], 2),
                                                   fmt(j["confidence"], 2),
                                                   fmt(math.hypot(math.log10(j["S"] / Sc),
                                                                  math.log10(j["R"] / Rc)), 2))
                   for j in cs)))
    out += ["", "**(d)** per column (runs below R_crit and from R = 1e-3: the share that is (d)):", "",
            "| S | (d) runs | their R | share of the column's runs at 1e-3 <= R < R_crit |",
            "|---|---|---|---|"]
    for S, col in cols.items():
        ds = [j for j in col if j["label"] == "d"]
        mid = [j for j in col if 1e-3 <= j["R"] < r_crit]
        share = ("%d of %d" % (sum(1 for j in mid if j["label"] == "d"), len(mid))) if mid else "-"
        out.append("| %s | %d | %s | %s |" % (fmt(S), len(ds),
                                             ", ".join(fmt(j["R"], 2) for j in ds) or "-", share))
    out.append("")
    return out
