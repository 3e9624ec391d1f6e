#!/usr/bin/env python3
"""Compares two gearmc output folders file by file, byte for byte, after removing what may differ
between runs of the same command on any number of MPI ranks and threads: the wall-time fields
(wall_s, time_s, contacts_per_s), the job's shape (ranks, threads), the time of the run (created_utc, and
the UTC time stamp in provenance lines) and the command's --threads value. With --any-version
also the version and the git commit of the binary (two builds' outputs, tests/bench/run_speed.sh).
Prints every difference and exits 1 when there is one, 0 otherwise.

usage: same_outputs.py [--any-version] DIR_A DIR_B
"""
import pathlib
import re
import sys

DROPPED = re.compile(rb'^\s*"(wall_s|time_s|contacts_per_s|ranks|threads|created_utc)": .*$', re.M)
TIME = re.compile(rb"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\dZ")
THREADS = re.compile(rb"--threads[ =]\d+")
VERSION_KEYS = re.compile(rb'^\s*"(version|git)": .*$', re.M)
VERSION = re.compile(rb"gearmc [0-9][0-9.]* \(git [0-9a-z.-]+\)")


def masked(path, any_version):
    data = path.read_bytes()
    if path.suffix == ".json":
        # gearmc writes one key per line: the lines of the dropped keys go (both files have them).
        data = DROPPED.sub(b"", data)
        if any_version:
            data = VERSION_KEYS.sub(b"", data)
    if any_version:
        data = VERSION.sub(b"gearmc VERSION", data)
    return THREADS.sub(b"--threads T", TIME.sub(b"TIME", data))


def files(root):
    return sorted(p.relative_to(root) for p in root.rglob("*") if p.is_file())


def main():
    args = sys.argv[1:]
    any_version = "--any-version" in args
    args = [x for x in args if x != "--any-version"]
    if len(args) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    a, b = pathlib.Path(args[0]), pathlib.Path(args[1])
    fa, fb = files(a), files(b)
    bad = 0
    if fa != fb:
        print(f"different file sets: {a}: {[str(f) for f in fa]}; {b}: {[str(f) for f in fb]}")
        bad += 1
    if not fa:
        print(f"no output files in {a}")
        bad += 1
    for f in sorted(set(fa) & set(fb)):
        ta, tb = masked(a / f, any_version), masked(b / f, any_version)
        if ta != tb:
            la, lb = ta.splitlines(), tb.splitlines()
            first = next((i for i in range(min(len(la), len(lb))) if la[i] != lb[i]),
                         min(len(la), len(lb)))
            print(f"{f}: differs from line {first + 1}:")
            print("  " + (la[first][:300].decode(errors="replace") if first < len(la) else "<end>"))
            print("  " + (lb[first][:300].decode(errors="replace") if first < len(lb) else "<end>"))
            bad += 1
    print(f"compared {len(fa)} files of {a} with {b}: {'identical' if not bad else 'DIFFERENT'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
