"""The paper's six example scenes (Blatny et al. 2022, Fig. 1), at phi = 0.4: class: (S, R).

One home for the studies in bench/ (the C++ tests keep theirs beside the test that runs them).
"""
PHI = 0.4
EXAMPLES = {
    "a": (4e-3, 1e-5),     # non-reflecting band
    "b": (4e-3, 4e-4),     # reflecting band
    "c": (4e-2, 2e-2),     # crossing bands
    "d": (1.32e-3, 4e-3),  # erratic
    "e": (1e-1, 1e-5),     # explosive compaction
    "f": (4e-3, 1e-1),     # buckling
}
