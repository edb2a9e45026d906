"""The phase map (the paper's Fig. 2) made by the service, and the runs around example (c) (README.md)."""
