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

# The Fig. 3 line: S = 4e-3 fixed, R rising through class (b), R/S^2 = 0.625 (the (a) point,
# example (a)) to 62.5; R = 4e-4 is example (b).
FIG3_S = 4e-3
FIG3_R = [1e-5, 2e-5, 4e-5, 7e-5, 1e-4, 1.4e-4, 2e-4, 3e-4, 4e-4, 6e-4, 1e-3]
