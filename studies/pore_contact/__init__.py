"""Pore contact: one grid velocity field or two across closing pores, measured on example (a) (README.md)."""
