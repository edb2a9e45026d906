#!/usr/bin/env python3
"""studies/validation/compacted_zone.py on columns whose band is known: a band from the top plate
at c_b/V = 2 that leaves its zone at twice the solid fraction (the mass balance's pair), the
same band with rows collapsing ahead of it, a column that only strains elastically, and
studies/lib/movie.py on a file laid out as schema/movie-format.md says."""
import json
import os
import struct
import tempfile
import unittest

from studies.validation import compacted_zone as cz
from studies.lib.movie import Movie

ROWS, PER_ROW, H0, PHI = 40, 60, 1.0, 0.4
L = H0 / ROWS
# Particles spread evenly over each unit-cell row (a lattice's row seen from afar).
Y_REF = [(j + (i + 0.5) / PER_ROW) * L for j in range(ROWS) for i in range(PER_ROW)]
STRAINS = [0.02 * k for k in range(1, 25)]


def banded(eps, speed=2.0):
    """The column at strain eps with a band from the top running at `speed` V: the material
    between the front and the top squeezed evenly under the plate, the rest at rest."""
    front = H0 - speed * eps * H0
    squeeze = (H0 * (1 - eps) - front) / (H0 - front)
    return [front + (y - front) * squeeze if y > front else y for y in Y_REF]


class FirstLeg(unittest.TestCase):
    def test_band_speed_and_zone(self):
        frames = [(e, banded(e)) for e in STRAINS]
        for level in cz.COMPACTING:  # a band that compacts in one step: one speed at any level
            leg = cz.first_leg(frames, ROWS * PER_ROW, ROWS, H0, PHI, level)
            self.assertAlmostEqual(leg["speed"], 2.0, delta=0.01)  # the edge's offset is constant
            self.assertAlmostEqual(leg["phi_f"], 2 * PHI, delta=0.01)  # 1/(1 - phi/phi_f) = 2
            self.assertEqual(leg["end"], "the bottom plate")
            self.assertGreaterEqual(leg["frames"], 20)

    def test_precursor_is_read_at_the_lower_level(self):
        """Material ahead of the band shortened by 1/6 (solid fraction up by a fifth) over a zone
        that widens by 20 L per unit strain, everything above it carried down by that
        shortening: the 1/8 edge runs at the zone's lower end, (2 + 20 L / h0) V = 2.5 V; the
        1/4 edge with the band, which the shortening carries down at 20 L / 6 per unit strain
        more, 2.083 V."""
        frames = []
        for e in STRAINS:
            front = H0 - 2.0 * e * H0
            width = 20 * L * e
            y = banded(e)
            lo = front - width
            y = [v - (min(v, front) - lo) / 6 if lo < v else v for v in y]
            frames.append((e, y))
        fast = cz.first_leg(frames, ROWS * PER_ROW, ROWS, H0, PHI, cz.COMPACTING[0])
        band = cz.first_leg(frames, ROWS * PER_ROW, ROWS, H0, PHI, cz.COMPACTING[1])
        self.assertAlmostEqual(fast["speed"], 2.0 + 20 * L / H0, delta=0.03)
        self.assertAlmostEqual(band["speed"], 2.0 + 20 * L / 6 / H0, delta=0.03)

    def test_compaction_ahead_ends_the_leg(self):
        frames = []
        lo, hi = 5 * L, 9 * L
        for e in STRAINS:
            y = banded(e)
            if e > 0.2 + 1e-9:  # rows 5-8 collapse to half their height, the rest above follow
                y = [v - 2 * L if v > hi else lo + (v - lo) / 2 if v > lo else v for v in y]
            frames.append((e, y))
        leg = cz.first_leg(frames, ROWS * PER_ROW, ROWS, H0, PHI)
        self.assertTrue(leg["end"].startswith("compaction ahead of the band"))
        # the collapsed rows span lo .. lo + 2 L; a window centre lies up to L above its bottom
        self.assertTrue(lo < leg["ahead_at"] < lo + 3 * L)
        self.assertAlmostEqual(leg["eps"][1], 0.2, delta=1e-9)
        self.assertAlmostEqual(leg["speed"], 2.0, delta=0.02)

    def test_elastic_column_has_no_band(self):
        frames = [(e, [y * (1 - e) for y in Y_REF]) for e in (0.002, 0.004, 0.006)]  # no band
        leg = cz.first_leg(frames, ROWS * PER_ROW, ROWS, H0, PHI)
        self.assertIsNone(leg["speed"])
        self.assertEqual(leg["frames"], 0)


class MovieFile(unittest.TestCase):
    def test_reads_the_documented_layout(self):
        n, eps = 3, 0.02
        qx, qy, level = [0, 32768, 65535], [65535, 0, 13107], [0, 255, 51]
        frame = struct.pack("<d", eps) + struct.pack("<3H", *qx) + struct.pack("<3H", *qy)
        frame += bytes(level)
        frame += bytes(-len(frame) % 8)
        header = b"CSMOVIE1" + struct.pack("<IIQQQ", 1, 96, n, 1, len(frame))
        header += struct.pack("<6d", 0.02, 0.0, 0.5, 0.0, 2.0, 4.0) + struct.pack("<II", 1, 0)
        self.assertEqual(len(header), 96)
        with tempfile.TemporaryDirectory() as d:
            with open(os.path.join(d, "movie.bin"), "wb") as f:
                f.write(header + frame)
            m = Movie(d)
            self.assertEqual((m.n, m.n_frames, m.periodic_x), (3, 1, True))
            e, x, y, rate = m.frame(0)
            self.assertEqual(e, eps)
            for got, want in ((x, [0.0, 0.5 * 32768 / 65535, 0.5]), (y, [2.0, 0.0, 0.4]),
                              (rate, [0.0, 1e4 - 1, 10 ** 0.8 - 1])):
                for g, w in zip(got, want):
                    self.assertAlmostEqual(g, w, delta=1e-9 * max(1.0, w))
            self.assertEqual(m.heights(0), (e, y))
            with self.assertRaises(IndexError):
                m.frame(1)
            with open(os.path.join(d, "movie.bin"), "r+b") as f:
                f.write(b"CSMOVIE2")
            with self.assertRaises(ValueError):
                Movie(d)


if __name__ == "__main__":
    unittest.main()
