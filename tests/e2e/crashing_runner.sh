#!/bin/sh
# A runner that crashes like a segfaulting engine would: used to check that a crash is isolated
# in the worker's child process, reported with its reason, and retried until max_attempts.
# It says the version of the real runner ($COMPACTION_REAL_RUNNER), as the worker asks at start.
if [ "${1:-}" = "--version" ]; then exec "$COMPACTION_REAL_RUNNER" --version; fi
echo '{"event":"start","n_particles":1,"eps_end":0.03}'
kill -SEGV $$
