"""Benchmarks of speed; bench/threads runs as modules (python3 -m bench.threads.long_run)."""
