#!/usr/bin/env bash
# Time, peak memory and report size of `gearmc diagnose` on 10⁵ and 10⁶ readings (not part of
# ctest). Readings: `gearmc simulate --master` of scenarios/p1_reference.yaml + probe lobing
# (6 lobes, 0.75 µm) + noise 0.3 µm, 2 400 readings per gear, so 42 gears ≈ 10⁵ and 417 gears
# ≈ 10⁶ readings; the model is p1_reference + noise 0.3 µm. Each size twice: the readings CSV
# (labelled), and the same points as a label-free table (only E = c − R n, in µm: each point
# matched to its flank, docs/formats.md). Needs GNU time (/usr/bin/time -v).
# Usage: tests/bench/diagnose_scale.sh [GEARMC] [GEARS...]   (default: build/gearmc 42 417)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
gearmc="${1:-$root/build/gearmc}"
shift || true
gears=("$@")
[[ ${#gears[@]} -gt 0 ]] || gears=(42 417)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
ref="$root/scenarios/p1_reference.yaml"
{ cat "$ref"; printf '\neffects:\n  probe_lobing: {harmonics: [{order: 6, amplitude_um: 0.75, phase_deg: 90}]}\n  noise: {sigma_um: 0.3}\n'; } >"$work/truth.yaml"
{ cat "$ref"; printf '\neffects:\n  noise: {sigma_um: 0.3}\n'; } >"$work/model.yaml"
printf 'columns: {x: X, y: Y, z: Z, run: Run}\nunit: um\n' >"$work/map.yaml"
printf '%-9s %-10s %-11s %-12s %-14s %s\n' gears readings input wall_s peak_rss_MB report_html_kB
for g in "${gears[@]}"; do
  "$gearmc" simulate "$work/truth.yaml" --master --gears "$g" --out "$work/r.csv" >/dev/null
  rows=$(($(wc -l <"$work/r.csv") - 3))
  # The label-free table: E = c - R n (R 0.5 mm, p1_reference's), µm, the run = the gear.
  awk -F, 'BEGIN { print "X,Y,Z,Run" } /^#/ || /^gear/ { next }
    { printf "%.4f,%.4f,%.4f,%s\n", 1000 * ($13 - 0.5 * $10), 1000 * ($14 - 0.5 * $11),
      1000 * ($15 - 0.5 * $12), $1 }' "$work/r.csv" >"$work/t.csv"
  for input in labelled label-free; do
    if [[ $input == labelled ]]; then
      measured=("$work/r.csv")
    else
      measured=("$work/t.csv" --columns "$work/map.yaml")
    fi
    /usr/bin/time -v "$gearmc" diagnose --model "$work/model.yaml" --measured "${measured[@]}" \
      --out "$work/out" >"$work/log" 2>&1
    wall=$(grep "Elapsed (wall clock)" "$work/log" | awk '{print $NF}')
    rss=$(grep "Maximum resident set size" "$work/log" | awk '{printf "%.0f", $NF / 1024}')
    html=$(($(stat -c %s "$work/out/report.html") / 1024))
    printf '%-9s %-10s %-11s %-12s %-14s %s\n' "$g" "$rows" "$input" "$wall" "$rss" "$html"
    rm -rf "$work/out"
  done
done
