# shellcheck shell=bash
# Shared by the whole-command timing scripts of tests/bench (source it): one timed run of a
# command, the median and the ratio of numbers.

# "wall_s cpu_s peak_rss_kb" of the command (CPU of it and its children: mpirun's ranks too),
# run in folder $1 (each run writes --out out there, so that the recorded command lines match).
measure() {
  local dir=$1
  shift
  rm -rf "$dir"
  mkdir -p "$dir"
  (cd "$dir" && /usr/bin/time -f "%e %U %S %M" -o times.txt "$@" --out out >/dev/null 2>run.err) || {
    echo "failed: $*" >&2
    cat "$dir/run.err" >&2
    exit 1
  }
  awk '{printf "%s %.2f %s\n", $1, $2 + $3, $4}' "$dir/times.txt"
}
median() { printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : 0.5 * (v[NR / 2] + v[NR / 2 + 1])}'; }
ratio() { awk -v a="$1" -v b="$2" -v f="${3:-1}" 'BEGIN {printf "%.3f", f * a / b}'; }
