#!/usr/bin/env bash
# Scaling of `gearmc run` over MPI ranks (docs/performance.md "Several processes"):
#  strong: the same run (GEARS gears of P1's reference) with --threads 1 in one process and with
#          `mpirun -n 2 --threads 1`, wall time of the whole command, median of 3 each, and the
#          efficiency t1 / (2 t2), and the CPU-time efficiency (CPU of one process / CPU of both
#          ranks: the decomposition's overhead, meaningful also on a loaded machine); the files of
#          both are compared byte for byte.
#  weak:   512 gears per rank on 1, 2, 4, 8 ranks (--oversubscribe: on a 2-core machine the
#          ranks share the cores, so only the reduction is of interest): the bytes of partial
#          results rank 0 receives (a binary tree: from ceil(log2 K) ranks), the time it waited
#          for them after its own share and the time it took to merge them, from the line gearmc
#          prints under mpirun.
# usage: tests/bench/mpi_scaling.sh [GEARS [strong|weak|both]]   (default 3000 both)
set -euo pipefail
cd "$(dirname "$0")/../.."
gearmc=$PWD/build/gearmc
gears=${1:-3000}
parts=${2:-both}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# "wall_s cpu_s" of the command (CPU time of it and its children: mpirun's ranks too), run in
# folder $1 (each run writes --out out there, so the command lines match).
measure() {
  local dir=$1; shift
  mkdir -p "$dir"
  (cd "$dir" && /usr/bin/time -f "%e %U %S" -o times.txt "$@" --out out >/dev/null 2>&1)
  awk '{printf "%s %.2f\n", $1, $2 + $3}' "$dir/times.txt"
}
median() { printf '%s\n' "$@" | sort -g | sed -n 2p; }
ratio() { awk -v a="$1" -v b="$2" -v f="${3:-1}" 'BEGIN {printf "%.3f", f * a / b}'; }

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
if [[ $parts != weak ]]; then
echo "== strong scaling: $gears gears"
one=() two=() cpu1=() cpu2=()
for k in 1 2 3; do
  read -r w c < <(measure "$work/one" "$gearmc" run --gears "$gears" --threads 1 --quiet)
  one+=("$w") cpu1+=("$c")
  read -r w c < <(measure "$work/two" mpirun --bind-to core -n 2 "$gearmc" run --gears "$gears" \
                    --threads 1 --quiet)
  two+=("$w") cpu2+=("$c")
done
t1=$(median "${one[@]}") t2=$(median "${two[@]}")
c1=$(median "${cpu1[@]}") c2=$(median "${cpu2[@]}")
echo "1 process, --threads 1:   wall ${one[*]} s -> median $t1 s; CPU median $c1 s"
echo "mpirun -n 2, --threads 1: wall ${two[*]} s -> median $t2 s; CPU median $c2 s"
echo "speed-up $(ratio "$t1" "$t2"), wall-time efficiency $(ratio "$t1" "$t2" 50) %"
echo "CPU-time efficiency (work of 1 process / work of the 2 ranks): $(ratio "$c1" "$c2" 100) %"
python3 tests/mpi/same_outputs.py "$work/one/out" "$work/two/out" | tail -1
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
fi
[[ $parts == strong ]] && exit 0

echo "== weak scaling: 512 gears per rank (--oversubscribe)"
printf "%6s %8s %10s %16s %18s %10s %10s\n" ranks gears messages bytes_at_rank_0 bytes_per_message wait_s merge_s
for n in 1 2 4 8 16; do
  g=$((512 * n))
  if [[ $n == 1 ]]; then
    printf "%6s %8s %10s %16s %18s %10s %10s\n" 1 "$g" 0 0 - - -
    continue
  fi
  line=$(mpirun --oversubscribe --bind-to none -n "$n" "$gearmc" run --gears "$g" --threads 1 \
           --quiet --out "$work/weak$n" | grep '^ranks ')
  bytes=$(echo "$line" | sed -E 's/^ranks [0-9]+: ([0-9]+) bytes.*/\1/')
  wait_s=$(echo "$line" | sed -E 's/.*waited ([0-9.e-]+) s.*/\1/')
  merge_s=$(echo "$line" | sed -E 's/.*merged in ([0-9.e-]+) s/\1/')
  messages=$(awk -v n="$n" 'BEGIN {m = 0; for (s = 1; s < n; s *= 2) m++; print m}')
  printf "%6s %8s %10s %16s %18s %10s %10s\n" "$n" "$g" "$messages" "$bytes" $((bytes / messages)) \
    "$wait_s" "$merge_s"
done
