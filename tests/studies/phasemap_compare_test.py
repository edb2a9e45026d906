#!/usr/bin/python3
"""studies/phase_map/compare.py on synthetic maps whose boundaries are known by construction.

The labels come from rules of R/S^2 (an (e)/(a) edge at 0.075, an (a)/(b) edge at 1.3) on the
same log lattice the map uses, so every bracket compare.py reports must contain the rule's value
and one R/S^2 must pass through all of them; a second map bends one boundary so that no single
value passes, and the longest stretch of columns that share one must be the unbent ones.
"""
import math
import unittest

from studies.phase_map import compare

PHI = 0.4


def lattice(n_s=9, n_r=17):
    """S from 1e-2 to 1e-1 and R from 1e-5 to 1e-1, a quarter decade apart in R."""
    return ([10 ** (-2 + k / (n_s - 1)) for k in range(n_s)],
            [10 ** (-5 + 4 * k / (n_r - 1)) for k in range(n_r)])


def job(S, R, label, c_b=None, n_r=0, runner_up=None):
    return {"S": S, "R": R, "label": label, "confidence": 0.9, "runner_up": runner_up,
            "n_reflections": n_r, "c_b": c_b, "wall": 1.0 / S}


def by_rule(edge_ea=0.075, edge_ab=1.3, bend=None):
    """(e) below R/S^2 = edge_ea, (a) up to edge_ab, (b) above; `bend` (S, factor) moves the
    (a)/(b) edge of columns at S >= bend[0] up by that factor."""
    ss, rs = lattice()
    jobs = []
    for S in ss:
        ab = edge_ab * (bend[1] if bend and S >= bend[0] else 1)
        for R in rs:
            q = R / S ** 2
            jobs.append(job(S, R, "e" if q < edge_ea else "a" if q < ab else "b"))
    return jobs


class Brackets(unittest.TestCase):
    def test_every_bracket_holds_the_rule_and_one_value_passes_all(self):
        cols = compare.columns(by_rule())
        for below, above, skip, edge in (("e", "a", (), 0.075), ("a", "b", ("e",), 1.3)):
            pairs = compare.brackets(cols, below, above, skip=skip)
            self.assertGreaterEqual(len(pairs), 3)
            for S, lo, hi in pairs:
                self.assertLess(compare.inertia(lo), edge)
                self.assertGreater(compare.inertia(hi), edge)
                self.assertAlmostEqual(math.log10(hi["R"] / lo["R"]), 0.25, places=9)
            lo, hi = compare.common_interval(pairs)
            self.assertTrue(lo < edge < hi, (lo, edge, hi))

    def test_a_bent_boundary_has_no_common_value_and_the_longest_stretch_is_the_straight_part(self):
        cols = compare.columns(by_rule(bend=(10 ** -1.25, 10.0)))
        pairs = compare.brackets(cols, "a", "b", skip=("e",))
        self.assertIsNone(compare.common_interval(pairs))
        first, last, (lo, hi) = compare.longest_common(pairs)
        self.assertEqual(first, 0)
        self.assertTrue(all(pairs[k][0] < 10 ** -1.25 for k in range(first, last + 1)))
        self.assertGreaterEqual(pairs[last + 1][0], 10 ** -1.25)
        self.assertTrue(lo < 1.3 < hi)

    def test_a_column_without_the_lower_class_gives_no_bracket(self):
        cols = compare.columns([job(0.01, 1e-5, "a"), job(0.01, 1e-4, "b")])
        self.assertEqual(compare.brackets(cols, "e", "a"), [])
        self.assertEqual(len(compare.brackets(cols, "a", "b", skip=("e",))), 1)


class Statistics(unittest.TestCase):
    def test_ranks_share_ties(self):
        self.assertEqual(compare.ranks([10, 20, 20, 5]), [2.0, 3.5, 3.5, 1.0])

    def test_rank_correlation_of_monotone_and_reversed_data(self):
        x = [1, 2, 3, 4, 5]
        self.assertAlmostEqual(compare.pearson(compare.ranks(x), compare.ranks([v ** 3 for v in x])), 1.0)
        self.assertAlmostEqual(compare.pearson(compare.ranks(x), compare.ranks([-v for v in x])), -1.0)

    def test_slope_of_a_power_law_in_log_log(self):
        q = [0.5, 1, 3, 10, 40]
        x = [math.log10(v) for v in q]
        y = [math.log10(2.0 * v ** 0.3) for v in q]
        self.assertAlmostEqual(compare.line_fit(x, y)[0], 0.3, places=12)

    def test_percentile_interpolates_between_order_statistics(self):
        self.assertEqual(compare.percentile([3, 1, 2], 0.5), 2)
        self.assertAlmostEqual(compare.percentile([0, 10], 0.1), 1.0)
        self.assertEqual(compare.percentile([7], 0.9), 7)


class Comparison(unittest.TestCase):
    def test_the_report_names_the_rule_and_flags_bands_below_the_mass_balance_floor(self):
        jobs = by_rule()
        floor = 1 / (1 - PHI)
        for j in jobs:  # a non-reflecting band at the floor, a reflecting one faster
            j["c_b"] = floor if j["label"] == "a" else 2.5 if j["label"] == "b" else None
            j["n_reflections"] = 2 if j["label"] == "b" else 0
        slow = jobs[0].copy()
        slow.update(label="a", c_b=0.9 * floor, S=0.5, R=1e-5)  # a column of its own
        text = "\n".join(compare.comparison(jobs + [slow], PHI, r_crit=0.07))
        self.assertIn("one R/S^2 passes through every bracket", text)
        self.assertIn("more than 5 % below that floor: 1 ((a) S 0.5 R 1e-05: 1.5)", text)
        # S = 0.1: (e), (a) and (b) upwards, each edge known to the lattice's quarter decade.
        self.assertIn("| 0.1 | 17 | 2 | 0.25 | 10 |", text)
        n_a = sum(1 for j in jobs if j["label"] == "a")
        self.assertIn("**c_b/V of (a)**, %d runs" % (n_a + 1), text)
        self.assertIn("within 5 %%: %d (" % n_a, text)
        self.assertIn("Spearman rank correlation of N_r with R/S^2: -.", text)  # N_r constant
        self.assertIn("**(c)**, 0 runs, nearest to the example (S = 0.04, R = 0.02) first: none.",
                      text)


if __name__ == "__main__":
    unittest.main()
