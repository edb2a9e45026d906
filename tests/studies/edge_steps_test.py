#!/usr/bin/env python3
"""studies/reference/edge_steps.py on a synthetic staircase edge: a front falling at c = 2 V that
stands for three frames and then drops a unit cell, as a band through the structure does. The
identity between the readings and the ends' offsets holds to round-off, the steps are found
whole, and starting late at a step's start gives the staircase's mean speed."""
import unittest

from studies.reference import edge_steps

CELL = 1 / 34
FRAME = 0.002
C = 2.0  # the staircase's mean speed / V: a cell per CELL / C of strain


def staircase(eps_from, eps_to, first_step_at):
    """Edge heights every frame: a drop of a cell every CELL / C of strain, the first at
    first_step_at."""
    pts = []
    for i in range(round(eps_from / FRAME), round(eps_to / FRAME) + 1):
        e = i * FRAME
        drops = max(0, int((e - first_step_at) / (CELL / C) + 1e-9) + 1) if e >= first_step_at else 0
        pts.append((e, 0.95 - drops * CELL))
    return pts


class EdgeSteps(unittest.TestCase):
    def test_transit_over_fit_is_the_ends_offsets(self):
        # 0.1 / 0.0147 = 6.8 steps: the ends fall at different places on a step
        for start in (0.020, 0.023, 0.027):
            r = edge_steps.edge_numbers(staircase(start, 0.2, 0.025), CELL, 0.06)
            strain = r["window"][1] - r["window"][0]
            self.assertAlmostEqual(r["transit"] / r["fit"] - 1,
                                   (r["first"] - r["last"]) * CELL / (r["fit"] * strain), places=12)

    def test_steps_of_a_cell_and_the_frames_in_between_stand(self):
        r = edge_steps.edge_numbers(staircase(0.02, 0.2, 0.025), CELL, 0.06)
        self.assertEqual(r["n_steps"], 12)  # drops at 0.025 + k 0.0147, k = 0..11, up to eps 0.2
        self.assertAlmostEqual(r["step"], 1.0, places=9)  # each drop is one frame of one cell
        self.assertAlmostEqual(r["standing"], 1 - 12 / 90, places=9)  # 91 frames, 90 moves
        # the fit of a staircase is its mean speed to within a step over its travel
        self.assertAlmostEqual(r["fit"], C, delta=0.05 * C)

    def test_a_rising_edge_reads_the_same(self):
        down = edge_steps.edge_numbers(staircase(0.02, 0.2, 0.025), CELL, 0.06)
        up = edge_steps.edge_numbers([(e, 1 - y) for e, y in staircase(0.02, 0.2, 0.025)], CELL, 0.06)
        for key in ("fit", "transit", "first", "last", "late_fit", "late_transit"):
            self.assertAlmostEqual(down[key], up[key], places=12, msg=key)


if __name__ == "__main__":
    unittest.main()
