"""Threads and whole runs timed: python3 -m bench.threads.before_after, python3 -m bench.threads.long_run."""
