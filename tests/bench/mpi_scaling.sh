#!/usr/bin/env bash
# Scaling of `gearmc run` over MPI ranks (docs/performance.md "Several processes"):
#  strong: tests/bench/strong_scaling.sh GEARS 3 (the same run with --threads 1 in one process
#          and with `mpirun --bind-to none -n 2 --threads 1`, interleaved, median of 3 each, the
#          wall-time and CPU-time efficiencies, the files of both compared byte for byte).
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

echo "machine: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
if [[ $parts != weak ]]; then
  echo "== strong scaling: $gears gears"
  tests/bench/strong_scaling.sh "$gears" 3
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
