#!/usr/bin/env bash
# Cost of the gear-parameter evaluation (`evaluation:`, docs/parameters.md): a 50-gear run of P1's
# gear with the typical CMM of scenarios/cmm_iso10360_typical.yaml (ISO class 5 tolerances)
# without evaluation, with the evaluation on the probing grid's own traces, and with 30-point
# profile and helix scans (scenarios/p1_reference_parameters.yaml). Each is the median of 5
# whole-process runs (start-up and output files included), wall time and CPU time (user +
# system, all threads); the ratio is against the run without evaluation.
# Usage: tests/bench/parameters_speed.sh [THREADS]   (default 1 thread: CPU time = wall time)
set -euo pipefail
cd "$(dirname "$0")/../.."
threads=${1:-1}
gearmc=build/gearmc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
base=scenarios/p1_reference_parameters.yaml
# Without the section (everything from `evaluation:` on removed).
sed '/^evaluation:/,$d' "$base" >"$work/none.yaml"
# The grid's own traces: the section without the scans.
sed -e 's/^  profile_points: 30 .*$/  profile_points: 0/' -e 's/^  helix_points: 30 .*$/  helix_points: 0/' \
  "$base" >"$work/grid.yaml"

median5() {
  local walls=() cpus=()
  for _ in 1 2 3 4 5; do
    /usr/bin/time -f '%e %U %S' -o "$work/time" "$@" >/dev/null
    read -r wall user sys <"$work/time"
    walls+=("$wall")
    cpus+=("$(echo "$user + $sys" | bc -l)")
  done
  echo "$(printf '%s\n' "${walls[@]}" | sort -g | sed -n 3p) $(printf '%s\n' "${cpus[@]}" | sort -g | sed -n 3p)"
}

run() { median5 "$gearmc" run "$1" --gears 50 --threads "$threads" --quiet --out "$work/out"; }
read -r nw nc <<<"$(run "$work/none.yaml")"
read -r gw gc <<<"$(run "$work/grid.yaml")"
read -r sw sc <<<"$(run "$base")"
printf '%-36s %8s %8s %8s\n' "50 gears, $threads thread(s), median of 5" "wall s" "CPU s" "CPU ratio"
printf '%-36s %8s %8s %8s\n' "no evaluation" "$nw" "$nc" "1.00"
printf '%-36s %8s %8s %8.2f\n' "evaluation on the grid's traces" "$gw" "$gc" "$(echo "$gc / $nc" | bc -l)"
printf '%-36s %8s %8s %8.2f\n' "evaluation with 30-point scans" "$sw" "$sc" "$(echo "$sc / $nc" | bc -l)"
