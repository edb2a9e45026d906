#!/usr/bin/env bash
# Proves the README's two commands on a clean Debian 12: makes a new Debian 12 (bookworm) root
# with debootstrap (minbase) from Debian's packages, clones the repository into it and runs, as
# root in that root (chroot):
#   1. scripts/main.sh for a bounded time: the server must answer (health, the dashboard page) and
#      the demonstration sweep must finish at least one job; then it is stopped with SIGTERM, as
#      Ctrl-C would, and must stop within a minute;
#   2. COMPACTION_TEST_QUICK=1 scripts/test.sh: the release build and every test not labelled
#      slow, without the sanitizer pass (see scripts/test.sh). The point is the install steps, a
#      real build and the tests that use what was installed (the browser, promtool); the slow ones
#      (this check among them: no recursion) run in the host's pass.
# It reports each step with its time, and the versions the commands ran with (Debian, node,
# chromium, cmake, g++), and exits non-zero when any step fails, also when debootstrap or the
# Debian mirror cannot be reached (it never skips). ctest runs it as fresh_machine_test
# (labels fresh, slow; tests/fresh/CMakeLists.txt), so only in the release pass of scripts/test.sh.
#
# What goes into the new root besides debootstrap's packages: the host's
# /etc/apt/sources.list.d/debian.sources (when there is one; else debootstrap's sources.list), its
# /etc/resolv.conf, and its certificate store (/etc/ssl/certs and /usr/local/share/ca-certificates),
# so that apt, npm and git trust what the host trusts. /proc, /sys, /dev, /dev/pts and a new
# /dev/shm are mounted; the network is the host's (the server gets a free port through
# COMPACTION_PORT instead of 8080). The commands run with an empty environment but PATH, HOME,
# LANG=C.UTF-8 and COMPACTION_IN_FRESH_CHECK=1 (this script refuses to run where that is set).
#
# The checkout: a `git clone` of the committed HEAD, which is what a new user gets: uncommitted
# changes are not in it (--worktree copies the working tree instead: the tracked files as they
# are and the untracked ones git does not ignore).
# Every run starts from a new, empty root (nothing is cached); on exit, also on failure or
# SIGINT/SIGTERM, the processes still running in it are killed by pid, everything mounted under
# it is unmounted, and it is removed (--keep keeps it, unmounted). A root an earlier run left
# behind (killed before it could clean up) is cleaned up at the start.
#
# usage: scripts/check-fresh-machine.sh [--dir DIR] [--logs DIR] [--keep] [--worktree]
#                                       [--budget SECONDS]
#   --dir DIR         where the new root is made (default /var/tmp; it needs about 3 GB)
#   --logs DIR        where each step's full output goes (default: a new folder under /tmp)
#   --keep            keep the root after the check (unmounted) to look into it
#   --worktree        copy the working tree (tracked and not ignored files) instead of cloning HEAD
#   --budget SECONDS  the whole check's time limit (default 2400); every step gets at most
#                     what is left, less three minutes to clean up, so that the check ends by
#                     itself before ctest's TIMEOUT (2700 s) would kill it without cleaning up
#   FRESH_MIRROR      the Debian mirror for debootstrap (default http://deb.debian.org/debian)
# Needs root (mount, chroot; it re-runs itself with sudo when it can), debootstrap (installed
# with apt-get when missing) and the network to the Debian mirror and the npm registry.
# Takes 11 minutes on 2 cores of its own, about 30 on shared ones (README.md has the times).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=lib/debian-root.sh
. "$repo/scripts/lib/debian-root.sh"   # debian_root_tools, debian_root_make, debian_root_host_apt
parent=/var/tmp
logs=""
keep=0
worktree=0
budget=2400
mirror="${FRESH_MIRROR:-http://deb.debian.org/debian}"
suite=bookworm
checkout=/root/compaction-sweep    # where the repository is cloned inside the new root
reserve=180                        # seconds kept back for the cleanup (2 to 3 min when loaded)

die() { echo "fresh: FAILED: $*" >&2; exit 1; }
while [ $# -gt 0 ]; do
  case "$1" in
    --dir) parent="${2:?--dir needs a folder}"; shift 2 ;;
    --logs) logs="${2:?--logs needs a folder}"; shift 2 ;;
    --keep) keep=1; shift ;;
    --worktree) worktree=1; shift ;;
    --budget) budget="${2:?--budget needs seconds}"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "check-fresh-machine.sh: unknown option '$1' (--help)" >&2; exit 2 ;;
  esac
done

[ -z "${COMPACTION_IN_FRESH_CHECK:-}" ] ||
  die "already inside a fresh-machine check (COMPACTION_IN_FRESH_CHECK is set): it does not run itself again"
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || die "needs root (debootstrap, mount, chroot), and there is no sudo"
  exec sudo "$0" "$@"
fi

t_start=$(date +%s)
deadline=$((t_start + budget))
fmt() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }
say() { echo "fresh: $*"; }
summary=()   # "step|seconds|result" lines, printed at the end
root=""

# --- cleanup: processes in a root, mounts under it, the root itself ----------------------------
mounts_under() { awk -v d="$1/" 'index($5 "/", d) == 1 { print $5 }' /proc/self/mountinfo | sort -r; }
pids_in() {
  local p l
  for p in /proc/[0-9]*; do
    l="$(readlink "$p/root" 2>/dev/null)" || continue
    case "$l" in "$1" | "$1"/*) echo "${p#/proc/}" ;; esac
  done
}
clean_root() {  # clean_root DIR KEEP: returns non-zero when a mount could not be removed
  local dir="$1" keep_it="$2" pids m left t_clean
  t_clean=$(date +%s)
  pids="$(pids_in "$dir")"
  if [ -n "$pids" ]; then
    say "cleanup: stopping $(echo $pids | wc -w) process(es) still running in $dir"
    kill -TERM $pids 2>/dev/null || true
    for _ in $(seq 50); do [ -z "$(pids_in "$dir")" ] && break; sleep 0.1; done
    pids="$(pids_in "$dir")"
    [ -z "$pids" ] || kill -KILL $pids 2>/dev/null || true
    sleep 0.5
  fi
  for m in $(mounts_under "$dir"); do umount "$m" 2>/dev/null || umount -l "$m" || true; done
  left="$(mounts_under "$dir")"
  if [ -n "$left" ]; then
    echo "fresh: cleanup: still mounted, $dir not removed: $left" >&2
    return 1
  fi
  if [ "$keep_it" = 1 ]; then
    rm -f "$dir/.compaction-fresh-check"   # not an abandoned root: the next run leaves it alone
    say "cleanup: kept $dir (unmounted; remove it with rm -rf --one-file-system $dir)"
  else
    rm -rf --one-file-system "$dir"
    say "cleanup: unmounted and removed $dir in $(fmt $(($(date +%s) - t_clean)))"
  fi
}
step_pid=""
on_exit() {
  local rc=$?
  trap - EXIT INT TERM
  [ -z "$step_pid" ] || kill -TERM "$step_pid" 2>/dev/null || true
  if [ -n "$root" ] && [ -d "$root" ]; then clean_root "$root" "$keep" || rc=1; fi
  exit "$rc"
}
trap on_exit EXIT
trap 'echo "fresh: FAILED: interrupted (SIGINT)" >&2; exit 130' INT
trap 'echo "fresh: FAILED: stopped (SIGTERM)" >&2; exit 143' TERM

# --- steps ---------------------------------------------------------------------------------------
# step NAME LIMIT CMD...: runs CMD (output to $logs/NAME.log) for at most LIMIT seconds and at most
# what the budget leaves; records its time; on failure prints the log's tail and exits. CMD runs
# in the background so that SIGINT and SIGTERM reach the cleanup at once.
left() { echo $((deadline - $(date +%s) - reserve)); }
step() {
  local name="$1" limit="$2" t0 rc=0 secs
  shift 2
  secs="$(left)"
  [ "$secs" -gt "$limit" ] && secs="$limit"
  [ "$secs" -gt 10 ] || die "$name: no time left in the budget of ${budget}s"
  say "$name: started (limit ${secs}s, log $logs/$name.log)"
  t0=$(date +%s)
  timeout -k 30 "$secs" "$@" >"$logs/$name.log" 2>&1 </dev/null &
  step_pid=$!
  wait "$step_pid" || rc=$?
  step_pid=""
  record "$name" "$t0" "$rc"
}
# step_fn NAME LIMIT FUNCTION: a step that runs one of the functions below in its own bash, with
# errexit (which a function called as `f || rc=$?` would not have) and the variables it reads.
step_fn() {
  step "$1" "$2" bash -c "$(declare -p root repo worktree checkout mirror suite); $(declare -f "$3");
    $(declare -f debian_root_tools debian_root_make debian_root_host_apt);
    set -euo pipefail; $3"
}
record() {  # record NAME T0 RC
  local dt=$(($(date +%s) - $2))
  if [ "$3" -eq 0 ]; then
    summary+=("$1|$dt|ok")
    say "$1: ok in $(fmt "$dt")"
    return 0
  fi
  summary+=("$1|$dt|FAILED")
  [ "$3" -eq 124 ] && echo "fresh: $1: timed out after $(fmt "$dt")" >&2
  if [ -f "$logs/$1.log" ]; then
    echo "fresh: $1: the last lines of $logs/$1.log:" >&2
    tail -n 60 "$logs/$1.log" | sed 's/^/  | /' >&2
  fi
  print_summary >&2
  die "$1 (exit $3)"
}
print_summary() {
  local line name dt res
  echo "fresh: summary ($source_desc; new Debian root in $parent)"
  printf '  %-22s %9s  %s\n' step time result
  for line in "${summary[@]}"; do
    IFS='|' read -r name dt res <<<"$line"
    printf '  %-22s %9s  %s\n' "$name" "$(fmt "$dt")" "$res"
  done
  printf '  %-22s %9s\n' total "$(fmt $(($(date +%s) - t_start)))"
}
# A command in the new root, with an empty environment but these (set once the root exists).
chroot_cmd=()
in_root() { "${chroot_cmd[@]}" "$@"; }

head="$(git -c safe.directory="$repo" -C "$repo" rev-parse --short HEAD)" || die "$repo is not a git checkout"
if [ "$worktree" = 1 ]; then
  source_desc="working tree of $repo at $head, copied"
else
  source_desc="HEAD $head of $repo, cloned"
fi
if [ -z "$logs" ]; then logs="$(mktemp -d /tmp/compaction-fresh-logs.XXXXXX)"; fi
mkdir -p "$logs" "$parent"
parent="$(cd "$parent" && pwd -P)"   # absolute: processes in the root are found by their root path
say "checking the README's two commands on a new Debian 12 root ($source_desc); logs in $logs"

# Roots of earlier runs that were killed before their cleanup (their pid is gone).
for old in "$parent"/compaction-fresh.*; do
  [ -f "$old/.compaction-fresh-check" ] || continue
  kill -0 "$(cat "$old/.compaction-fresh-check")" 2>/dev/null && continue
  say "removing the root an earlier run left behind: $old"
  clean_root "$old" 0 || die "could not clean up $old"
done

host_tools() {
  debian_root_tools "$mirror" "$suite"
  command -v git chroot mount timeout
}
step_fn host-tools 600 host_tools

root="$(mktemp -d "$parent/compaction-fresh.XXXXXX")"
chmod 755 "$root"
echo $$ >"$root/.compaction-fresh-check"
chroot_cmd=(chroot "$root" /usr/bin/env -i PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin
  HOME=/root LANG=C.UTF-8 TERM=dumb COMPACTION_IN_FRESH_CHECK=1)
make_root() { debian_root_make "$root" "$mirror" "$suite"; }
step_fn debootstrap 900 make_root

prepare() {
  debian_root_host_apt "$root"
  cp -L /etc/resolv.conf "$root/etc/resolv.conf"
  mount -t proc proc "$root/proc"
  mount -t sysfs sysfs "$root/sys"
  mount --bind /dev "$root/dev"
  mount --bind /dev/pts "$root/dev/pts"
  mount -t tmpfs -o mode=1777,size=2g tmpfs "$root/dev/shm"
  if [ "$worktree" = 1 ]; then
    mkdir -p "$root$checkout"
    git -c safe.directory="$repo" -C "$repo" ls-files -z --cached --others --exclude-standard |
      (cd "$repo" && tar --null --ignore-failed-read -T - -cf -) | tar -C "$root$checkout" --no-same-owner -xf -
    cp -r "$repo/.git" "$root$checkout/.git"   # for the source revision the build records
  else
    git -c safe.directory="$repo" clone -q --no-hardlinks "$repo" "$root$checkout"
  fi
  git -C "$root$checkout" log -1 --format='checkout: %h %s'
  cat "$root/etc/debian_version"
}
step_fn prepare 300 prepare

# The main job, in the background: the server must answer and the demo sweep finish one job.
port=""
for p in $(seq 18080 18179); do (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null || { port=$p; break; }; done
[ -n "$port" ] || die "no free port in 18080-18179 for the server"
url="http://127.0.0.1:$port"
main_limit=1500
[ "$(left)" -lt "$main_limit" ] && main_limit="$(left)"
say "main: started: scripts/main.sh with COMPACTION_PORT=$port (limit ${main_limit}s, log $logs/main.log)"
t0=$(date +%s)
setsid "${chroot_cmd[@]}" bash -c "cd $checkout && COMPACTION_PORT=$port exec scripts/main.sh" >"$logs/main.log" 2>&1 </dev/null &
main_pid=$!
answered=""
succeeded=0
while :; do
  now=$(date +%s)
  if ! kill -0 "$main_pid" 2>/dev/null; then
    rc=0; wait "$main_pid" || rc=$?
    echo "scripts/main.sh exited ($rc) before the demo sweep finished a job" >>"$logs/main.log"
    [ "$rc" -ne 0 ] || rc=1
    record main "$t0" "$rc"
  fi
  if [ $((now - t0)) -ge "$main_limit" ]; then
    echo "no finished job after ${main_limit}s (server answered: ${answered:-no})" >>"$logs/main.log"
    record main "$t0" 124
  fi
  if [ -z "$answered" ] && in_root curl -fsS -m 5 "$url/api/v1/health" >/dev/null 2>&1; then
    answered=$((now - t0))
    summary+=("  server answers|$answered|(install, build, start)")
    say "main: the server answers on $url after $(fmt "$answered") (install, build, start)"
    in_root curl -fsS -m 5 "$url/" | grep -q '<script type="module" src="js/main.js">' ||
      { echo "the dashboard page $url/ is not the dashboard" >>"$logs/main.log"; record main "$t0" 1; }
    in_root curl -fsS -m 5 -o /dev/null "$url/js/main.js" ||
      { echo "the dashboard's js/main.js is not served" >>"$logs/main.log"; record main "$t0" 1; }
  fi
  if [ -n "$answered" ]; then
    counts="$(in_root curl -fsS -m 5 "$url/api/v1/sweeps?limit=1" 2>/dev/null | in_root python3 -c '
import json, sys
s = json.load(sys.stdin)["sweeps"]
c = s[0]["counts"] if s else {}
print(c.get("succeeded", 0), c.get("failed", 0), c.get("total", 0))' 2>/dev/null)" || counts=""
    read -r succeeded failed total <<<"${counts:-0 0 0}"
    [ "$failed" -eq 0 ] ||
      { echo "the demo sweep has $failed failed job(s)" >>"$logs/main.log"; record main "$t0" 1; }
    [ "$succeeded" -ge 1 ] && break
  fi
  sleep 5
done
summary+=("  first job done|$(($(date +%s) - t0))|($succeeded of $total)")
say "main: the demo sweep finished $succeeded of $total jobs after $(fmt $(($(date +%s) - t0))); stopping it with SIGTERM"
kill -TERM "$main_pid"
stopped=""
for _ in $(seq 600); do kill -0 "$main_pid" 2>/dev/null || { stopped=1; break; }; sleep 0.1; done
rc=0; [ -n "$stopped" ] && { wait "$main_pid" || rc=$?; }
if [ -z "$stopped" ]; then echo "scripts/main.sh did not stop within 60 s of SIGTERM" >>"$logs/main.log"; record main "$t0" 1; fi
grep -q '^stopped; the database stays in' "$logs/main.log" ||
  { echo "scripts/main.sh did not report a clean stop" >>"$logs/main.log"; record main "$t0" 1; }
sleep 1
if [ -n "$(pids_in "$root")" ]; then
  echo "processes left running after scripts/main.sh stopped: $(pids_in "$root")" >>"$logs/main.log"
  record main "$t0" 1
fi
say "main: stopped (exit $rc), no process left"
record main "$t0" 0

step test 1800 "${chroot_cmd[@]}" bash -c "cd $checkout && COMPACTION_TEST_QUICK=1 scripts/test.sh"
ctest_secs="$(sed -n 's/^Total Test time (real) = *\([0-9]*\).*/\1/p' "$logs/test.log" | tail -1)"
[ -z "$ctest_secs" ] || summary+=("  of which ctest|$ctest_secs|($(grep -o '[0-9]* tests failed out of [0-9]*' "$logs/test.log" | tail -1))")
grep -E 'tests passed|Total Test time' "$logs/test.log" | tail -2 | sed 's/^/fresh: test: /'
sed -n '/The following tests did not run/,/^$/p' "$logs/test.log" | sed 's/^/fresh: test: /'

versions() {
  echo "Debian $(cat "$root/etc/debian_version") ($(. "$root/etc/os-release" && echo "$VERSION_CODENAME"))"
  echo "node $(in_root node --version)"
  echo "npm $(in_root npm --version)"
  echo "playwright-core $(in_root node -p "require('$checkout/tests/browser/node_modules/playwright-core/package.json').version")"
  echo "@redocly/cli $(in_root node -p "require('$checkout/tests/browser/node_modules/@redocly/cli/package.json').version")"
  echo "chromium $(in_root chromium --version | awk '{print $2}')"
  echo "cmake $(in_root cmake --version | awk 'NR == 1 {print $3}')"
  echo "g++ $(in_root g++ -dumpfullversion) ($(in_root g++ --version | sed -n '1s/^g++ (\(.*\)) .*/\1/p'))"
  echo "ninja $(in_root ninja --version)"
  echo "python3 $(in_root python3 --version | awk '{print $2}')"
  echo "host kernel $(uname -r)"
}
versions >"$logs/versions.log" 2>&1 || record versions "$(date +%s)" 1
say "versions: $(paste -sd ';' "$logs/versions.log" | sed 's/;/, /g')"
print_summary
say "ok: both commands work on a new Debian 12 root"
