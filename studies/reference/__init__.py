"""The converged reference: examples (a) and (b) at rising resolution, and ensembles of perturbed runs (README.md)."""
