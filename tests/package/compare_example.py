#!/usr/bin/env python3
"""Compares the C++ example's statistics (examples/run_scenario, printed with 17 digits) with the
summary.json that `gearmc run` wrote for the same scenario and gear count: two routes to the same
run (the API and the command line) must agree exactly. Usage: compare_example.py OUTPUT SUMMARY"""
import json
import re
import sys

output = open(sys.argv[1]).read()
summary = json.load(open(sys.argv[2]))
rows = re.findall(r"^point (left|right) n (\d+) mean (\S+) std (\S+) max (\S+) p95 (\S+)$",
                  output, re.M)
if len(rows) != 2:
    sys.exit(f"expected two 'point' lines in the example's output, got:\n{output}")
for side, n, mean, std, vmax, p95 in rows:
    stats = summary["delta_rcomp_um"]["point"][side]
    for key, text in (("mean", mean), ("std", std), ("max", vmax), ("p95", p95)):
        if float(text) != stats[key]:
            sys.exit(f"point {side} {key}: example {text}, summary.json {stats[key]!r}")
    if int(n) != stats["n"] or int(n) == 0:
        sys.exit(f"point {side} n: example {n}, summary.json {stats['n']}")
print("example and summary.json agree:", ", ".join(f"{r[0]} n {r[1]}" for r in rows))
