#!/usr/bin/env bash
# Submits compaction-worker processes to Slurm (docs/cluster.md): N workers of C CPUs each, as a
# job array (one job per worker, each starts when its CPUs are free) or as one job of N srun
# tasks (all start together). Prints the Slurm job id.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"

usage() {
  cat <<USAGE
usage: scripts/slurm/submit-workers.sh --server URL --workers N --time TIME [options] [-- worker flags]
  --server URL           the compaction-server the workers lease from (reachable from the nodes)
  --workers N            how many workers
  --time TIME            Slurm time limit of each array task or of the srun job (sbatch --time)
  --cpus-per-worker C    CPUs of each worker, its --threads (1)
  --token-file FILE      the worker token, a file only its owner can read (chmod 600); read on the
                         node, never put on a command line
  --partition P          Slurm partition (the cluster's default)
  --array | --srun       a job array (the default) or one job with N srun tasks
  --idle-exit SECONDS    each worker exits after this long without a job (300; 0: never)
  --max-jobs N           each worker exits after N jobs (0: no limit)
  --signal-seconds S     SIGTERM this long before the time limit, so that a worker gives its lease
                         back before Slurm kills it (120; Slurm may send it up to 60 s earlier)
  --bin DIR              the folder of compaction-worker and compaction-run, on a filesystem the
                         nodes see (the build's bin/ next to this repository)
  --output PATTERN       sbatch --output (Slurm's default: slurm-%A_%a.out, slurm-%j.out)
  --job-name NAME        sbatch --job-name (compaction-workers)
  --dry-run              print the sbatch command instead of running it
  flags after --         passed to every compaction-worker (--poll-interval, --log-level, ...)
Other sbatch options from the environment: SBATCH_ACCOUNT, SBATCH_QOS, ... (man sbatch).
USAGE
}
die() { echo "submit-workers.sh: $*" >&2; exit 2; }
need_value() { (($1 >= 2)) || die "$2 needs a value (--help)"; }
positive_int() { [[ "$2" =~ ^[1-9][0-9]*$ ]] || die "$1 must be a positive integer, got '$2'"; }
count() { [[ "$2" =~ ^[0-9]+$ ]] || die "$1 must be a non-negative integer, got '$2'"; }
seconds() { [[ "$2" =~ ^[0-9]+(\.[0-9]+)?$ ]] || die "$1 must be a number of seconds, got '$2'"; }

server="" workers="" time_limit="" cpus=1 token_file="" partition="" mode=array
idle_exit=300 max_jobs=0 signal_seconds=120 bin="$here/../../build/bin" output="" dry_run=0
job_name=compaction-workers
while (($#)); do
  case "$1" in
    --server) need_value $# "$1"; server="$2"; shift 2 ;;
    --workers) need_value $# "$1"; positive_int "$1" "$2"; workers="$2"; shift 2 ;;
    --time) need_value $# "$1"; time_limit="$2"; shift 2 ;;
    --cpus-per-worker) need_value $# "$1"; positive_int "$1" "$2"; cpus="$2"; shift 2 ;;
    --token-file) need_value $# "$1"; token_file="$2"; shift 2 ;;
    --partition) need_value $# "$1"; partition="$2"; shift 2 ;;
    --array) mode=array; shift ;;
    --srun) mode=srun; shift ;;
    --idle-exit) need_value $# "$1"; seconds "$1" "$2"; idle_exit="$2"; shift 2 ;;
    --max-jobs) need_value $# "$1"; count "$1" "$2"; max_jobs="$2"; shift 2 ;;
    --signal-seconds) need_value $# "$1"; positive_int "$1" "$2"; signal_seconds="$2"; shift 2 ;;
    --bin) need_value $# "$1"; bin="$2"; shift 2 ;;
    --output) need_value $# "$1"; output="$2"; shift 2 ;;
    --job-name) need_value $# "$1"; job_name="$2"; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    -h|--help) usage; exit 0 ;;
    --) shift; break ;;
    *) die "unknown option '$1' (--help)" ;;
  esac
done
[ -n "$server" ] || die "--server is missing (--help)"
[[ "$server" =~ ^https?:// ]] || die "--server must be an http:// or https:// URL, got '$server'"
[ -n "$workers" ] || die "--workers is missing (--help)"
[ -n "$time_limit" ] || die "--time is missing (--help)"
bin_dir="$(cd "$bin" 2>/dev/null && pwd)" || die "--bin: no folder $bin (build first: scripts/build.sh)"
bin="$bin_dir"
for exe in compaction-worker compaction-run; do
  [ -x "$bin/$exe" ] || die "--bin: $bin/$exe is not an executable file"
done
batch_args=(--bin "$bin")
if [ -n "$token_file" ]; then
  [ -r "$token_file" ] || die "--token-file: cannot read $token_file"
  mode_bits="$(stat -c %a "$token_file")"
  [[ "$mode_bits" =~ 00$ ]] || die "--token-file: $token_file can be read by others (mode $mode_bits): chmod 600 $token_file"
  batch_args+=(--token-file "$(cd "$(dirname "$token_file")" && pwd)/$(basename "$token_file")")
fi

sbatch_args=(--parsable --job-name="$job_name" --time="$time_limit" --cpus-per-task="$cpus")
# The SIGTERM before the time limit goes to the workers themselves: an array task's batch shell
# is its worker (B:); in the srun job it goes to the tasks, not to srun, which would answer it by
# killing them (compaction-workers.sbatch).
if [ "$mode" = array ]; then
  sbatch_args+=(--array="0-$((workers - 1))" --ntasks=1 --signal="B:TERM@$signal_seconds")
else
  sbatch_args+=(--ntasks="$workers" --signal="TERM@$signal_seconds")
fi
[ -z "$partition" ] || sbatch_args+=(--partition="$partition")
[ -z "$output" ] || sbatch_args+=(--output="$output")
# The job keeps the environment it is submitted from (sbatch --export=ALL); tokens stay out of it.
unset COMPACTION_WORKER_TOKEN COMPACTION_SUBMIT_TOKEN
command=(sbatch "${sbatch_args[@]}" "$here/compaction-workers.sbatch" "${batch_args[@]}"
         --server "$server" --idle-exit "$idle_exit" --max-jobs "$max_jobs" "$@")
if ((dry_run)); then
  printf '%q ' "${command[@]}"; echo
  exit 0
fi
job="$("${command[@]}")" || die "sbatch failed (exit $?)"
echo "${job%%;*}"
