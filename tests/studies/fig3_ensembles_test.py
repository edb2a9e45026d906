#!/usr/bin/env python3
"""studies/validation/fig3_ensembles.py's reading of an ensemble, and the statistics of
studies/lib/spread.py it uses: a point counts as (b) only when more than half its runs are, the
rank correlation is +1 exactly when the speeds rise at every step, and --points takes only the
line's own R values."""
import argparse
import unittest

from studies.validation import fig3_ensembles
from studies.lib.spread import line_fit, spearman, stats


class Majority(unittest.TestCase):
    def test_more_than_half(self):
        self.assertEqual(fig3_ensembles.majority(["b", "b", "a"]), "b")
        self.assertEqual(fig3_ensembles.majority(["d"]), "d")

    def test_a_tie_is_no_label(self):
        self.assertEqual(fig3_ensembles.majority(["b", "c"]), "mixed")
        self.assertEqual(fig3_ensembles.majority(["a", "b", "b", "a"]), "mixed")


class Points(unittest.TestCase):
    def test_line_values_sorted_once(self):
        self.assertEqual(fig3_ensembles.r_list("4e-4,2e-5,0.0004"), [2e-5, 4e-4])

    def test_other_values_refused(self):
        for text in ("3e-4,5", "", "x"):
            with self.assertRaises(argparse.ArgumentTypeError):
                fig3_ensembles.r_list(text)


class Spread(unittest.TestCase):
    def test_spearman(self):
        x = [1.0, 2.0, 3.0, 4.0]
        self.assertEqual(spearman(x, [1.5, 1.6, 2.0, 9.0]), 1.0)
        self.assertEqual(spearman(x, [9.0, 2.0, 1.6, 1.5]), -1.0)
        self.assertLess(spearman(x, [1.5, 2.0, 1.6, 9.0]), 1.0)

    def test_line_fit(self):
        slope, err = line_fit([0.0, 1.0, 2.0, 3.0], [1.0, 3.0, 5.0, 7.0])
        self.assertAlmostEqual(slope, 2.0, places=12)
        self.assertAlmostEqual(err, 0.0, places=12)
        slope, err = line_fit([0.0, 1.0, 2.0], [0.0, 1.0, 0.0])  # residuals 1/3, -2/3, 1/3
        self.assertEqual(slope, 0.0)
        self.assertAlmostEqual(err, (2 / 3 / 1 / 2) ** 0.5, places=12)
        self.assertEqual(line_fit([0.0, 2.0], [1.0, 0.0]), (-0.5, None))
        self.assertEqual(line_fit([1.0], [1.0]), (None, None))

    def test_stats_of_one_and_of_several(self):
        self.assertIsNone(stats([1.9])["sd"])
        st = stats([1.0, None, 3.0, float("nan")])
        self.assertEqual((st["n"], st["mean"], st["sd"]), (2, 2.0, 2 ** 0.5))
        self.assertIsNone(stats([None]))


if __name__ == "__main__":
    unittest.main()
