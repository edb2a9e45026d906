# Sourced by the command-line tests (tests/*/..._cli_test.sh): a scratch folder $out removed on
# exit, `check NAME COMMAND...` counting a pass when COMMAND succeeds and printing the failures,
# and `checks_done` printing the counts and failing when any check failed.
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail=0; pass=0
check() {  # check NAME CONDITION...
  local name="$1"; shift
  if "$@"; then pass=$((pass + 1)); else echo "FAILED: $name"; fail=$((fail + 1)); fi
}
checks_done() {  # checks_done [WHAT]
  echo "${1:+$1: }$pass passed, $fail failed"
  test $fail -eq 0
}
