"""The spread of a reading over an ensemble of runs (perturbed particles, several seeds)."""
import argparse
import math


def stats(values):
    """Mean, sample standard deviation and range of the finite values; None where there are
    none (the standard deviation is None for a single value)."""
    v = [x for x in values if x is not None and math.isfinite(x)]
    if not v:
        return None
    mean = sum(v) / len(v)
    sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else None
    return {"n": len(v), "mean": mean, "sd": sd, "min": min(v), "max": max(v)}


def line_fit(xs, ys):
    """Least-squares slope of ys on xs and its standard error: (None, None) with fewer than two
    points, the error None with two."""
    n = len(xs)
    if n < 2:
        return None, None
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    if n < 3:
        return slope, None
    resid = sum((y - my - slope * (x - mx)) ** 2 for x, y in zip(xs, ys))
    return slope, math.sqrt(resid / (n - 2) / sxx)


def ranks(v):
    order = sorted(range(len(v)), key=lambda i: v[i])
    out = [0.0] * len(v)
    for r, i in enumerate(order):
        out[i] = float(r)
    return out


def spearman(x, y):
    """Rank correlation (no ties expected): +1 when y rises with x at every step."""
    rx, ry = ranks(x), ranks(y)
    n = len(x); m = (n - 1) / 2
    sxy = sum((a - m) * (b - m) for a, b in zip(rx, ry))
    sxx = sum((a - m) ** 2 for a in rx)
    return sxy / sxx if sxx else float("nan")


def seed_list(text):
    """argparse type of --seeds: a comma list of whole numbers, at least one, none twice."""
    try:
        seeds = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError("a comma list of whole numbers, got %r" % text)
    if not seeds or len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError("at least one seed, none twice, got %r" % text)
    return seeds
