"""Numerical stability over the (S, R, phi) box and under pathological numerics (README.md)."""
