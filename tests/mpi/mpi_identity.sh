#!/usr/bin/env bash
# Runs `gearmc run` (with points.csv), `gearmc uncertainty`, `gearmc sweep` and `gearmc check` in one
# process and
# under `mpirun --oversubscribe -n 1, 2, 3` with other thread counts, and checks with
# same_outputs.py that every output file is the same byte for byte (wall times, ranks, threads and
# the time stamp aside). The run has 3 blocks of 256 gears (600 gears), so 2 ranks get 1 and 2
# blocks and 3 ranks one each; the small probing grid and the probe-lobing effect chain keep it at
# a few seconds. Then the error contract: bad input seen by all ranks, and an output folder that only
# rank 0 opens: one message, exit 2, nothing written, no rank left waiting.
# Exit 77 (ctest: skipped) only when mpirun is not installed.
# usage: mpi_identity.sh GEARMC SOURCE_DIR WORK_DIR
set -euo pipefail
gearmc=$(realpath "$1")
src=$(realpath "$2")
work=$3
if ! command -v mpirun >/dev/null; then
  echo "SKIPPED: mpirun not found (scripts/setup-deps installs openmpi-bin)"
  exit 77
fi
# mpirun refuses root unless told; shared memory without ptrace (containers).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1
# Under the sanitizers (scripts/test --sanitize sets ASAN_OPTIONS): Open MPI's leaks at
# MPI_Finalize are suppressed (lsan_openmpi.supp); the suppressions match only fully unwound stacks
# of components that are still loaded.
if [[ -n ${ASAN_OPTIONS:-} ]]; then
  export ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0"
  export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$src/tests/mpi/lsan_openmpi.supp:fast_unwind_on_malloc=0"
  export OMPI_MCA_mca_base_component_disable_dlclose=1
fi
mpi() { local n=$1; shift; mpirun --oversubscribe --bind-to none -n "$n" "$gearmc" "$@"; }
compare="python3 $src/tests/mpi/same_outputs.py"
rm -rf "$work" && mkdir -p "$work" && cd "$work"

# The scenario: P2's probe-lobing scenario on 2 teeth with 3 × 2 points per flank.
sed -e 's/points_along_profile: 10/points_along_profile: 3/' \
    -e 's/sections_across_face: 5/sections_across_face: 2/' -e 's/teeth: all/teeth: [1, 13]/' \
    "$src/scenarios/p2_probe_mean6.yaml" > small.yaml
grep -q "teeth: \[1, 13\]" small.yaml

run_case() {  # DIR RANKS THREADS ARGS…: the command in its own folder with --out out
  local dir=$1 ranks=$2 threads=$3; shift 3
  mkdir -p "$dir" && cp ./*.yaml "$dir/"
  if compgen -G "./*.csv" >/dev/null; then cp ./*.csv "$dir/"; fi  # a scenario's tables
  if [[ $ranks == 0 ]]; then
    (cd "$dir" && "$gearmc" "$@" --threads "$threads" --quiet --out out >log.txt 2>&1)
  else
    (cd "$dir" && mpi "$ranks" "$@" --threads "$threads" --quiet --out out >log.txt 2>&1)
  fi
}

fail=0
echo "== run: 600 gears with points.csv"
run_case run_single 0 1 run small.yaml --gears 600 --points
for case in "1 2" "2 1" "3 1" "2 2"; do
  set -- $case
  run_case "run_n$1_t$2" "$1" "$2" run small.yaml --gears 600 --points
  grep -q '"ranks": '"$1" "run_n$1_t$2/out/summary.json" || { echo "summary.json lacks ranks $1"; fail=1; }
  $compare run_single/out "run_n$1_t$2/out" || fail=1
done
wc -l run_single/out/points.csv

echo "== run with gear parameters (evaluation:): 300 gears, 2 blocks"
cp "$src/scenarios/p1_reference_parameters.yaml" params.yaml
run_case params_single 0 1 run params.yaml --gears 300
for case in "2 1" "3 1"; do
  set -- $case
  run_case "params_n$1_t$2" "$1" "$2" run params.yaml --gears 300
  grep -q '"F_alpha"' "params_n$1_t$2/out/summary.json" || { echo "summary.json lacks F_alpha"; fail=1; }
  $compare params_single/out "params_n$1_t$2/out" || fail=1
done

echo "== run on machines drawn for a data sheet and its verification table (cmm:): 300 gears"
cp "$src/scenarios/p1_cmm_verified.yaml" cmm.yaml
cp "$src/scenarios/cmm_verification_example.csv" .
sed -i -e 's/points_along_profile: 10/points_along_profile: 3/' \
  -e 's/sections_across_face: 5/sections_across_face: 2/' cmm.yaml
run_case cmm_single 0 1 run cmm.yaml --gears 300
run_case cmm_n2_t1 2 1 run cmm.yaml --gears 300
grep -q '"machines_kept"' cmm_n2_t1/out/summary.json || { echo "summary.json lacks cmm"; fail=1; }
$compare cmm_single/out cmm_n2_t1/out || fail=1

echo "== uncertainty: adaptive (mass calibration) and a fixed M"
model=$src/scenarios/uncertainty/mass_calibration.yaml
run_case unc_single 0 1 uncertainty "$model"
run_case fixed_single 0 2 uncertainty "$model" --trials 300001
for n in 2 3; do
  run_case "unc_n$n" "$n" 1 uncertainty "$model"
  $compare unc_single/out "unc_n$n/out" || fail=1
  run_case "fixed_n$n" "$n" 1 uncertainty "$model" --trials 300001
  $compare fixed_single/out "fixed_n$n/out" || fail=1
done

echo "== sweep: 2 × 2 variants over 3 ranks"
sweep_args=(sweep small.yaml --vary stylus.radius_mm=0.4,0.6 --vary probing.points_along_profile=3,4 --gears 40 --statistic delta_rcomp.point.p95 --at-most 1)
run_case sweep_single 0 1 "${sweep_args[@]}"
run_case sweep_n3 3 1 "${sweep_args[@]}"
$compare sweep_single/out sweep_n3/out || fail=1
# The bands travel from the ranks with each point's per-gear values: they must exist to be compared.
python3 -c "import json,sys; p=json.load(open('sweep_n3/out/sweep.json'))['points']; sys.exit(0 if all(x['both_band_um'] for x in p) else 1)" \
  || { echo "sweep: a point without a band"; fail=1; }

echo "== check: a max claim runs to the budget of 1100 gears (batches 256, 256, 512, 76)"
cp small.yaml claims.yaml
cat >> claims.yaml <<'YAML'
claims:
  - {name: point_p95, quantity: delta_rcomp.point, statistic: {quantile: 0.95}, at_most_um: 20.0,
     confidence: 0.95}
  - {name: flank_max, quantity: delta_rcomp.flank_max, statistic: max, at_most_um: 1000.0,
     confidence: 0.95}
YAML
run_case check_single 0 1 check claims.yaml --max-gears 1100
for case in "2 1" "3 2"; do
  set -- $case
  run_case "check_n$1_t$2" "$1" "$2" check claims.yaml --max-gears 1100
  grep -q '"ranks": '"$1" "check_n$1_t$2/out/check.json" || { echo "check.json lacks ranks $1"; fail=1; }
  grep -q '"gears": 1100' "check_n$1_t$2/out/check.json" || { echo "check did not run 1100 gears"; fail=1; }
  # check.json: the verdicts, bounds and gear counts (the report and JUnit file carry wall times).
  mkdir -p "cj_single" "cj_n$1_t$2"
  cp check_single/out/check.json cj_single/ && cp "check_n$1_t$2/out/check.json" "cj_n$1_t$2/"
  $compare cj_single "cj_n$1_t$2" || fail=1
done

echo "== errors"
expect_error() {  # DIR EXPECTED_CODE ARGS…: one gearmc message, the exit code, no out/
  local dir=$1 code=$2; shift 2
  mkdir -p "$dir" && cp small.yaml "$dir/"
  set +e
  (cd "$dir" && mpi 2 "$@" >log.txt 2>err.txt)
  local got=$?
  set -e
  local messages
  messages=$(grep -c '^gearmc: ' "$dir/err.txt" || true)
  if [[ $got != "$code" || $messages != 1 || -e $dir/out ]]; then
    echo "$dir: exit $got (expected $code), $messages gearmc messages (expected 1), out/ exists: $([[ -e $dir/out ]] && echo yes || echo no)"
    cat "$dir/err.txt"
    fail=1
  else
    echo "$dir: exit $got, one message: $(grep '^gearmc: ' "$dir/err.txt")"
  fi
}
expect_error err_input 2 run missing.yaml --quiet --out out
expect_error err_sweep 2 sweep small.yaml --vary stylus.radius_mm=0.5,-1 --quiet --out out
# rank 0 cannot create its output folder (a file is in the way); the other rank must not hang.
mkdir -p err_folder && touch err_folder/blocked
expect_error err_folder 2 run small.yaml --gears 600 --quiet --out blocked/out
exit $fail
