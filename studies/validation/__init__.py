"""Validation against the paper's examples: labels, band speeds, Fig. 3, invariance, solid fractions, random structures, 3D (README.md)."""
