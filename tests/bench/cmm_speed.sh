#!/usr/bin/env bash
# Cost of measuring on machines drawn for a data sheet (`cmm:`, docs/cmm.md) against the same run
# with today's per-effect machine errors: scenarios/p1_cmm_mpe.yaml (thermal expansion, servo step,
# cmm_geometry and cmm_probing on 1 000 kept machines) and the same scenario with its `cmm:` section
# replaced by the effects of scenarios/cmm_iso10360_typical.yaml (scale, squareness, drift,
# noise). Whole-process runs (the machines' draw at start-up and the output files included), the
# two interleaved, medians of N; the ratio is of CPU time (user + system).
# Usage: tests/bench/cmm_speed.sh [GEARS] [N] [THREADS]   (default 2000 gears, 5 runs, 1 thread)
set -euo pipefail
cd "$(dirname "$0")/../.."
source tests/bench/bench_lib.sh
gears=${1:-2000}
n=${2:-5}
threads=${3:-1}
gearmc=$PWD/build/gearmc
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp scenarios/p1_cmm_mpe.yaml "$work/cmm.yaml"
sed -e '/^cmm:/,$d' scenarios/p1_cmm_mpe.yaml >"$work/today.yaml"
sed -e '/^  step_quantization:/a\
  scale: {x_ppm: {uniform: [-2, 2]}, y_ppm: {uniform: [-2, 2]}, z_ppm: {uniform: [-2, 2]}}\
  squareness: {xy_urad: {uniform: [-5, 5]}, xz_urad: {uniform: [-5, 5]}, yz_urad: {uniform: [-5, 5]}}\
  drift: {x_um: {uniform: [-0.5, 0.5]}, y_um: {uniform: [-0.5, 0.5]}, z_um: {uniform: [-0.5, 0.5]}}\
  noise: {sigma_um: 0.3}' -i "$work/today.yaml"
today_cpu=() cmm_cpu=() today_wall=() cmm_wall=()
for _ in $(seq "$n"); do
  read -r w c _ <<<"$(measure "$work/t" "$gearmc" run "$work/today.yaml" --gears "$gears" --threads "$threads" --quiet)"
  today_wall+=("$w") today_cpu+=("$c")
  read -r w c _ <<<"$(measure "$work/c" "$gearmc" run "$work/cmm.yaml" --gears "$gears" --threads "$threads" --quiet)"
  cmm_wall+=("$w") cmm_cpu+=("$c")
done
tc=$(median "${today_cpu[@]}") cc=$(median "${cmm_cpu[@]}")
printf '%-44s %8s %8s\n' "$gears gears, $threads thread(s), median of $n" "wall s" "CPU s"
printf '%-44s %8s %8s\n' "today's effects (scale, squareness, drift, noise)" "$(median "${today_wall[@]}")" "$tc"
printf '%-44s %8s %8s\n' "cmm: kept machines (geometry, probing)" "$(median "${cmm_wall[@]}")" "$cc"
echo "CPU ratio cmm / today: $(ratio "$cc" "$tc")  (runs: today ${today_cpu[*]}; cmm ${cmm_cpu[*]})"
