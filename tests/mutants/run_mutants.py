#!/usr/bin/env python3
"""Applies each hand-written mutant of tests/mutants/ to a copy of the sources, rebuilds, runs the
tests and prints which tests killed it (scripts/mutants is the entry point).

A mutant is one plausible bug (a flipped comparison, an off-by-one, a dropped factor) kept as a
unified diff, tests/mutants/NN-name.patch, whose lines before the diff say what it breaks. For
each one, in the copy build-mutants/src (built in build-mutants/build, no unity build, so one
mutant recompiles one file):
  1. the patch is applied (a patch that no longer applies is an error: refresh it);
  2. the build runs (a mutant that does not compile is "invalid", not counted as killed);
  3. the tests of behaviour run: every ctest test but the stored references (label `reference`,
     and GoogleTest suites named *Regression) and those labelled `slow` (mpi_identity,
     package_consumer, fuzz_commands), stopping at the first failure; a failure or a timeout
     kills the mutant;
  4. if none failed, the stored-reference tests run: a failure there is "references only";
  5. the patch is reversed.
The score is the share of valid mutants killed by tests of behaviour; docs/contributing.md
quotes the last one. Results also go to build-mutants/results.csv.
"""
import argparse
import csv
import filecmp
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MUTANTS = ROOT / "tests" / "mutants"
WORK = ROOT / "build-mutants"
SRC = WORK / "src"
BUILD = WORK / "build"
SKIP_DIRS = {".git", "results"}


def source_dirs():
    return [p for p in ROOT.iterdir()
            if not p.name.startswith("build") and p.name not in SKIP_DIRS]


def sync_sources():
    """Copies the working tree's sources into SRC, rewriting only files that differ (so that the
    build recompiles what changed, and nothing else)."""
    copied = 0
    for top in source_dirs():
        paths = [top] if top.is_file() else [Path(d) / f for d, _, fs in os.walk(top) for f in fs]
        for p in paths:
            rel = p.relative_to(ROOT)
            dst = SRC / rel
            if dst.exists() and filecmp.cmp(p, dst, shallow=False):
                continue
            dst.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(p, dst)
            shutil.copymode(p, dst)
            copied += 1
    return copied


def run(cmd, cwd=None, timeout=None):
    return subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, errors="replace", timeout=timeout)


def build():
    if not (BUILD / "build.ninja").exists():
        r = run(["cmake", "-S", str(SRC), "-B", str(BUILD), "-G", "Ninja",
                 "-DCMAKE_BUILD_TYPE=Release", "-DGEARMC_UNITY_BUILD=OFF",
                 "-DCMAKE_EXPORT_COMPILE_COMMANDS=OFF"])
        if r.returncode != 0:
            sys.exit("mutants: cmake failed:\n" + r.stdout[-4000:])
    return run(["cmake", "--build", str(BUILD), "-j", str(os.cpu_count() or 1)])


def ctest(label_args, timeout_s):
    """Runs ctest; returns (passed, first failing test or '')."""
    r = run(["ctest", "--test-dir", str(BUILD), "-j", str(os.cpu_count() or 1),
             "--timeout", str(timeout_s), "--stop-on-failure", "--output-on-failure"] + label_args)
    if r.returncode == 0:
        return True, ""
    failed = re.findall(r"^\s*\d+ - (\S+) \(", r.stdout, re.M)
    if not failed:
        failed = re.findall(r"Test\s+#\d+: (\S+) \.+\*+\s*(?:Failed|Timeout|Exception)", r.stdout)
    return False, failed[0] if failed else "(ctest failed: " + r.stdout.strip()[-200:] + ")"


# Stored references: the ctest label `reference` (regression_tests), any GoogleTest suite named
# *Regression (a change detector kept beside the unit tests, e.g. CheckRegression) and the
# README's transcripts (ReadmeExamples: gearmc's own output, pasted into the README).
STORED = r"Regression\.|ReadmeExamples\."
BEHAVIOUR = ["-LE", "reference|slow", "-E", STORED]
REFERENCE = [["-L", "reference"], ["-R", STORED, "-LE", "slow"]]


def reference_tests(timeout_s):
    """Runs the stored references; returns (passed, first failing test or '')."""
    for args in REFERENCE:
        ok, first = ctest(args, timeout_s)
        if not ok:
            return ok, first
    return True, ""


def describe(patch):
    """The patch's first line (its name and what it breaks)."""
    for line in patch.read_text().splitlines():
        if line.strip():
            return line.strip()
    return patch.stem


def patched_files(patch):
    return re.findall(r"^\+\+\+ b/(\S+)", patch.read_text(), re.M)


def apply(patch, reverse=False):
    args = ["patch", "-p1", "--forward", "--no-backup-if-mismatch", "-s", "-i", str(patch)]
    if reverse:
        args = ["patch", "-p1", "-R", "--no-backup-if-mismatch", "-s", "-i", str(patch)]
    return run(args, cwd=SRC)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="comma-separated name parts: run the matching mutants only")
    ap.add_argument("--no-baseline", action="store_true",
                    help="skip the run of the unmutated tests (they must pass for a fair score)")
    ap.add_argument("--timeout", type=int, default=300, help="seconds per test")
    ap.add_argument("--min-score", type=float, default=90.0,
                    help="exit 1 below this percentage killed by tests of behaviour")
    a = ap.parse_args()

    patches = sorted(MUTANTS.glob("*.patch"))
    if a.only:
        parts = a.only.split(",")
        patches = [p for p in patches if any(x in p.name for x in parts)]
    if not patches:
        sys.exit("mutants: no patch matches")
    WORK.mkdir(exist_ok=True)
    # A patch left applied by an interrupted run is undone by copying the sources again.
    print("mutants: %d source files copied to %s" % (sync_sources(), SRC), flush=True)
    b = build()
    if b.returncode != 0:
        sys.exit("mutants: the unmutated sources do not build:\n" + b.stdout[-4000:])
    if not a.no_baseline:
        ok, first = ctest(BEHAVIOUR + ["--schedule-random"], a.timeout)
        ok_ref, first_ref = reference_tests(a.timeout)
        if not ok or not ok_ref:
            sys.exit("mutants: the unmutated tests fail (%s): fix them first" % (first or first_ref))
        print("mutants: the unmutated tests pass", flush=True)

    rows = []
    for patch in patches:
        t0 = time.time()
        files = patched_files(patch)
        r = apply(patch)
        if r.returncode != 0:
            sync_sources()
            sys.exit("mutants: %s no longer applies (refresh it against %s):\n%s" %
                     (patch.name, ", ".join(files), r.stdout))
        try:
            b = build()
            if b.returncode != 0:
                outcome, by = "invalid", "does not compile"
            else:
                ok, first = ctest(BEHAVIOUR, a.timeout)
                if not ok:
                    outcome, by = "killed", first
                else:
                    ok_ref, first_ref = reference_tests(a.timeout)
                    outcome, by = ("references only", first_ref) if not ok_ref else ("survived", "")
        finally:
            if apply(patch, reverse=True).returncode != 0:
                sync_sources()
        rows.append((patch.name, outcome, by, describe(patch), time.time() - t0))
        print("%-44s %-16s %s  (%.0f s)" % (patch.name, outcome, by, time.time() - t0),
              flush=True)
    build()  # leave the copy built as its sources are

    with open(WORK / "results.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mutant", "outcome", "first failing test", "what it breaks", "seconds"])
        for row in rows:
            w.writerow([row[0], row[1], row[2], row[3], "%.0f" % row[4]])
    valid = [r for r in rows if r[1] != "invalid"]
    killed = sum(r[1] == "killed" for r in rows)
    refs = sum(r[1] == "references only" for r in rows)
    survived = [r for r in rows if r[1] == "survived"]
    score = 100.0 * killed / len(valid) if valid else 0.0
    print("\n| mutants | killed by behaviour tests | references only | survived | invalid |")
    print("|---:|---:|---:|---:|---:|")
    print("| %d | %d | %d | %d | %d |" % (len(rows), killed, refs, len(survived),
                                         len(rows) - len(valid)))
    print("score: %.0f %% killed by tests of behaviour (%d of %d valid mutants)" %
          (score, killed, len(valid)))
    for r in survived:
        print("survived: %s — %s" % (r[0], r[3]))
    return 0 if score >= a.min_score else 1


if __name__ == "__main__":
    sys.exit(main())
