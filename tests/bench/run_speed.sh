#!/usr/bin/env bash
# Whole-command speed of `gearmc run` (README's speed table, docs/performance.md): GEARS gears of
# P1's reference scenario with the default threads (all cores), REPEATS times; prints the wall
# time, CPU time and peak RSS of every run and their medians. With OLD_GEARMC (another build, e.g.
# the last version's build/gearmc) the two binaries run interleaved (old, new, old, new, …) so that
# a change of the machine's load hits both alike, the ratio of the medians is printed, and the
# outputs of the last run of each are compared file by file (tests/mpi/same_outputs.py
# --any-version: the same statistics, figures and report apart from the version, the wall times
# and the time stamps); exit 1 if they differ. Both run as `gearmc` from their own folder on PATH,
# so their recorded command lines are the same.
# Measure on an idle machine: on a shared one the wall times mean little.
# usage: tests/bench/run_speed.sh [GEARS [REPEATS [OLD_GEARMC]]]   (default 77000 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
gears=${1:-77000}
repeats=${2:-3}
old=${3:-}
[[ $gears =~ ^[1-9][0-9]*$ && $repeats =~ ^[1-9][0-9]*$ ]] || {
  echo "usage: $0 [GEARS [REPEATS [OLD_GEARMC]]] (positive integers, a gearmc binary)" >&2
  exit 2
}
[[ -z $old || -x $old ]] || { echo "$0: OLD_GEARMC '$old' is not an executable" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin-new" "$work/bin-old"
cp build/gearmc "$work/bin-new/gearmc"
[[ -n $old ]] && cp "$old" "$work/bin-old/gearmc"

# measure, median, ratio
source tests/bench/bench_lib.sh

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "gearmc run --gears $gears --quiet, $repeats repeats${old:+, interleaved with $old}"
versions=(new)
[[ -n $old ]] && versions=(old new)
declare -A walls cpus rss
for ((k = 0; k < repeats; ++k)); do
  for v in "${versions[@]}"; do
    read -r w c m < <(measure "$work/$v" env PATH="$work/bin-$v:$PATH" gearmc run \
      --gears "$gears" --quiet)
    walls[$v]+="$w " cpus[$v]+="$c " rss[$v]+="$m "
  done
done
for v in "${versions[@]}"; do
  # shellcheck disable=SC2086  # the lists split into their numbers on purpose
  echo "$v: wall ${walls[$v]}s -> median $(median ${walls[$v]}) s; CPU ${cpus[$v]}s -> median" \
    "$(median ${cpus[$v]}) s; peak RSS ${rss[$v]}kB -> median $(median ${rss[$v]}) kB"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
if [[ -n $old ]]; then
  # shellcheck disable=SC2086
  echo "speed-up old/new (median wall times): $(ratio "$(median ${walls[old]})" \
    "$(median ${walls[new]})")"
  python3 tests/mpi/same_outputs.py --any-version "$work/old/out" "$work/new/out"
fi
