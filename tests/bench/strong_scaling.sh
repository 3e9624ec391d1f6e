#!/usr/bin/env bash
# Strong scaling of `gearmc run` from 1 to 2 MPI ranks (docs/performance.md "Several
# processes"): the same run of GEARS gears of P1's reference scenario, as one process with
# --threads 1 and as `mpirun --bind-to none -n 2 … --threads 1`, the two commands interleaved
# (one, two, one, two, …) REPEATS times each so that a change of the machine's load hits both
# alike. Prints every wall and CPU time, the medians, the speed-up T1 / T2, the wall-time
# efficiency T1 / (2 T2) and the CPU-time efficiency (CPU of one process / CPU of both ranks: the
# decomposition's own overhead — start-up, each rank's set-up, the reduction — meaningful also
# on a loaded machine). Then it checks that the output files of the last run of each are the same
# byte for byte apart from what records the job (tests/mpi/same_outputs.py: the command's
# --threads, wall times, ranks, threads, time stamps); exit 1 if they differ.
# Measure the efficiency on an idle machine: on a shared one the wall times mean little.
# usage: tests/bench/strong_scaling.sh [GEARS [REPEATS]]   (default 3000 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
gearmc=$PWD/build/gearmc
gears=${1:-3000}
repeats=${2:-3}
[[ $gears =~ ^[1-9][0-9]*$ && $repeats =~ ^[1-9][0-9]*$ ]] || {
  echo "usage: $0 [GEARS [REPEATS]] (positive integers)" >&2
  exit 2
}
command -v mpirun >/dev/null || { echo "mpirun not found (scripts/setup-deps installs it)" >&2; exit 2; }
# OpenMPI refuses root without these; the single-copy mechanism (CMA) is not allowed in
# containers.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# measure, median, ratio
source tests/bench/bench_lib.sh

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "strong scaling: $gears gears, $repeats interleaved repeats"
one=() two=() cpu1=() cpu2=()
for ((k = 0; k < repeats; ++k)); do
  read -r w c _ < <(measure "$work/one" "$gearmc" run --gears "$gears" --threads 1 --quiet)
  one+=("$w") cpu1+=("$c")
  read -r w c _ < <(measure "$work/two" mpirun --bind-to none -n 2 "$gearmc" run --gears "$gears" \
    --threads 1 --quiet)
  two+=("$w") cpu2+=("$c")
done
t1=$(median "${one[@]}") t2=$(median "${two[@]}")
c1=$(median "${cpu1[@]}") c2=$(median "${cpu2[@]}")
echo "1 process, --threads 1:   wall ${one[*]} s -> median $t1 s; CPU ${cpu1[*]} s -> median $c1 s"
echo "mpirun -n 2, --threads 1: wall ${two[*]} s -> median $t2 s; CPU ${cpu2[*]} s -> median $c2 s"
echo "speed-up T1/T2 $(ratio "$t1" "$t2"), wall-time efficiency T1/(2 T2) $(ratio "$t1" "$t2" 50) %"
echo "CPU-time efficiency (work of 1 process / work of the 2 ranks): $(ratio "$c1" "$c2" 100) %"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
python3 tests/mpi/same_outputs.py "$work/one/out" "$work/two/out"
