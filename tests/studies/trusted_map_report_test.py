#!/usr/bin/python3
"""studies/trusted_map/report.py: the trusted map's readings on a synthetic export.

Two levels over three S columns: at level 0, (a) up to R/S^2 = 1 and (b) from 4; at level 1
the boundary moves up, (a) to 4 and (b) from 16, so the point at R/S^2 = 4 changes its label;
one (b) lies below an (a) at level 0 of the second column, an overlap the report must name.
The readings are counted by hand from these points.
"""
import unittest

from studies.trusted_map import report as rep


def point(S, x, label, cells, robust=True, share=1.0, speed=None):
    return {"S": S, "R": x * S * S, "cells_per_unit": cells, "label": label, "robust": robust,
            "share": share, "band_speed_ratio": speed}


REQUEST = {"adaptive": {"S": {"min": 1e-3, "max": 1e-2}, "R": {"min": 1e-6, "max": 1e-2},
                        "resolution_decades": 0.5, "levels": [{"preset": "default"},
                                                              {"cells_per_strut": 8}]},
           "replicates": {"n": 4, "perturbation": 0.01}}


def export():
    pts = []
    for S in (1e-3, 3e-3, 1e-2):
        pts += [point(S, 1.0, "a", 20), point(S, 4.0, "b", 20, robust=(S != 3e-3), share=0.75),
                point(S, 16.0, "b", 20)]
        pts += [point(S, 1.0, "a", 36), point(S, 4.0, "a", 36),
                point(S, 16.0, "b", 36, speed={"mean": 2.5, "sd": 0.1, "n": 4})]
    pts.append(point(3e-3, 8.0, "a", 20))  # an (a) above the (b) at 4: an overlap
    pts.append(point(1e-2, 64.0, None, 36))  # not finished yet: no label
    jobs = [{"state": "succeeded", "cells_per_unit": 20, "result": {"wall_seconds": w}}
            for w in (60, 70, 80)]
    jobs += [{"state": "succeeded", "cells_per_unit": 36, "result": {"wall_seconds": 720}},
             {"state": "failed", "cells_per_unit": 36, "result": None}]
    return {"points": pts, "jobs": jobs, "sweep": {"request": REQUEST}}


class TrustedMapReport(unittest.TestCase):
    def setUp(self):
        self.export = export()
        self.grids = rep.grids_of(self.export["points"], REQUEST)
        self.levels = rep.by_level(self.export["points"], self.grids)

    def test_levels_are_the_grids_coarse_first(self):
        self.assertEqual(self.grids, [20, 36])
        self.assertEqual(len(self.levels[0]), 10)
        self.assertEqual(len(self.levels[1]), 10)

    def test_a_level_without_points_is_named_by_the_request(self):
        only_coarse = [p for p in self.export["points"] if p["cells_per_unit"] == 20]
        self.assertEqual(rep.grids_of(only_coarse, REQUEST), [20, None])

    def test_robust_share_at_the_finest_level(self):
        best = rep.finest(self.levels)
        # Nine nodes at level 1 (the unlabelled one stays out) and the level-0 node at 8.
        self.assertEqual(len(best), 10)
        counts = rep.robust_per_class([p for _, p in best.values()])
        self.assertEqual(counts, {"a": (7, 7), "b": (3, 3)})
        level0 = rep.robust_per_class(self.levels[0].values())
        self.assertEqual(level0["b"], (6, 5))

    def test_changed_names_each_node_whose_label_moved(self):
        moved = rep.changed(self.levels)
        self.assertEqual([labels for _, labels in moved], [["b", "a"]] * 3)
        self.assertEqual([round(float(n[1]) / float(n[0]) ** 2, 6) for n, _ in moved], [4.0] * 3)

    def test_boundary_brackets_and_overlap(self):
        fine = rep.boundary(list(self.levels[1].values()))
        self.assertEqual((fine["below"], fine["above"]), (4.0, 16.0))
        self.assertAlmostEqual(fine["middle"], 8.0)
        self.assertAlmostEqual(fine["half_decades"], 0.5 * 0.6020599913, places=9)
        coarse = rep.boundary(list(self.levels[0].values()))
        self.assertIsNone(coarse["middle"])
        self.assertEqual([(p["label"], round(rep.x_of(p), 6)) for p in coarse["overlap"]],
                         [("b", 4.0), ("b", 4.0), ("b", 4.0), ("a", 8.0)])
        self.assertIsNone(rep.boundary([point(1e-3, 1.0, "a", 20)]))

    def test_agreement_counts_nodes_labelled_at_both(self):
        self.assertEqual(rep.agreement(self.levels, 0, 1), (6, 9))

    def test_cost_counts_succeeded_runs_per_level(self):
        hours = rep.run_hours(self.export["jobs"], self.grids)
        self.assertEqual(hours[0]["runs"], 3)
        self.assertAlmostEqual(hours[0]["hours"], 210 / 3600)
        self.assertEqual(hours[0]["median_s"], 70)
        self.assertEqual(hours[1]["runs"], 1)
        # S over one decade and R over four at half a decade: 3 x 9 nodes.
        self.assertEqual(rep.lattice_points(REQUEST), 27)
        text = "\n".join(rep.cost_lines(REQUEST, hours, self.levels))
        self.assertIn("27 lattice points at level 1 with 4 replicates", text)
        self.assertIn("%.1f CPU-hours" % (27 * 4 * 720 / 3600), text)

    def test_the_report_names_every_section(self):
        text = "\n".join(rep.report(self.export))
        for heading in ("## Levels", "## Robust labels per class", "## Points whose label changed",
                        "## The (a)/(b) boundary", "## c_b/V of (b)", "## Cost and agreement"):
            self.assertIn(heading, text)
        self.assertIn("2.5 +- 0.1 (n 4)", text)


if __name__ == "__main__":
    unittest.main()
