#!/usr/bin/env bash
# Speed of `gearmc uncertainty` against the same models in NumPy (vectorised, as suncal does):
# JCGM 101 §9.3 (mass calibration) at 10^6 trials, and §9.2 (normal inputs) with the adaptive
# procedure at p = 0.9973. Each is the median wall time of 5 whole-process runs (start-up and
# output files included on both sides). Usage: tests/bench/uncertainty_speed.sh [THREADS] (2).
# Needs a built build/gearmc and python3-numpy (scripts/setup-deps).
set -euo pipefail
cd "$(dirname "$0")/../.."
threads=${1:-2}
gearmc=build/gearmc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/coverage_probability: 0.95/coverage_probability: 0.9973/' -e 's/^name: .*/name: additive_9973/' \
  scenarios/uncertainty/additive_normal.yaml >"$work/additive_9973.yaml"

# median of 5 wall times (s) of the command
median5() {
  local times=()
  for _ in 1 2 3 4 5; do
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null
    t1=$(date +%s.%N)
    times+=("$(echo "$t1 - $t0" | bc -l)")
  done
  printf '%s\n' "${times[@]}" | sort -g | sed -n 3p
}

g93=$(median5 "$gearmc" uncertainty scenarios/uncertainty/mass_calibration.yaml --trials 1000000 \
  --threads "$threads" --quiet --out "$work/m")
g92=$(median5 "$gearmc" uncertainty "$work/additive_9973.yaml" --threads "$threads" --quiet \
  --out "$work/a")
n93=$(median5 /usr/bin/python3 tests/bench/uncertainty_numpy.py mass 1000000)
n92=$(median5 /usr/bin/python3 tests/bench/uncertainty_numpy.py adaptive 0.9973)
trials92=$(grep -o '"trials": [0-9]*' "$work/a/uncertainty.json" | head -1 | grep -o '[0-9]*')

printf 'gearmc uncertainty speed (median of 5, %s threads, %s cores, load %s)\n' "$threads" \
  "$(nproc)" "$(cut -d' ' -f1 /proc/loadavg)"
printf '%-46s %10s %10s %8s\n' "model" "gearmc s" "NumPy s" "ratio"
printf '%-46s %10.3f %10.3f %8.2f\n' "JCGM 101 §9.3 mass calibration, 10^6 trials" "$g93" "$n93" \
  "$(echo "$n93 / $g93" | bc -l)"
printf '%-46s %10.3f %10.3f %8.2f\n' "§9.2 adaptive, p = 0.9973 ($trials92 trials)" "$g92" "$n92" \
  "$(echo "$n92 / $g92" | bc -l)"
echo "goals: §9.3 at 10^6 under 0.5 s on 2 cores; adaptive §9.2 at 0.9973 under 2 s"
