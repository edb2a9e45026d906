"""Run time against error: the numerics of a run against the error of its label and band speed (README.md)."""
