#!/usr/bin/env python3
"""Docs that cannot drift: every transcript in README.md and docs/*.md is run and compared.

A transcript is a fenced block right after the line `<!-- transcript -->`. Its lines that start
with `$ ` are commands (a line ending in a backslash continues on the next; run with bash from a scratch folder in which `build/gearmc` is the binary
under test and `scenarios/` the repository's; a trailing `# comment` is part of the shell line and
ignored by bash); the lines after a command, up to the next command, are what it prints (stdout,
then stderr). A line `…` stands for any number of lines (the example shows only part of the
output). Durations (`in 0.11 s`, `0.5 s` at the end of a line) are compared as `<t> s`: they are
the machine's, not the program's.

  tests/docs/transcripts.py --gearmc build/gearmc            check: exit 1 and a diff per block
  tests/docs/transcripts.py --gearmc build/gearmc --update   rewrite the blocks (not those with …)

scripts/update-docs runs the second; the ctest `docs_transcripts` the first.
"""
import argparse
import difflib
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile

MARKER = "<!-- transcript -->"
ELISION = "…"
DURATION = [
    (re.compile(r"\bin \d+(\.\d+)? s\b"), "in <t> s"),
    (re.compile(r"(?<=\s)\d+(\.\d+)? s$"), "<t> s"),
]


def masked(line):
    for pattern, replacement in DURATION:
        line = pattern.sub(replacement, line)
    return line.rstrip()


def blocks(path):
    """(first line index of the block's body, its lines) of each marked block of a file."""
    lines = path.read_text(encoding="utf-8").split("\n")
    found = []
    k = 0
    while k < len(lines):
        if lines[k].strip() == MARKER:
            if k + 1 >= len(lines) or not lines[k + 1].startswith("```"):
                raise SystemExit(f"{path}:{k + 1}: {MARKER} must be followed by a fenced block")
            start = k + 2
            end = start
            while end < len(lines) and not lines[end].startswith("```"):
                end += 1
            if end == len(lines):
                raise SystemExit(f"{path}:{k + 2}: the transcript's block is not closed")
            found.append((start, lines[start:end]))
            k = end
        k += 1
    return lines, found


def steps(body, where):
    """[(command, expected lines)] of a block."""
    out = []
    continued = False
    for line in body:
        if continued:  # the command's previous line ended with a backslash
            out[-1] = (out[-1][0] + "\n" + line, [])
            continued = line.endswith("\\")
        elif line.startswith("$ "):
            out.append((line[2:], []))
            continued = line.endswith("\\")
        elif not out:
            raise SystemExit(f"{where}: a transcript starts with a `$ ` command line")
        else:
            out[-1][1].append(line)
    return out


def run(command, scratch, timeout):
    done = subprocess.run(["bash", "-c", command], cwd=scratch, capture_output=True, text=True,
                          timeout=timeout)
    text = done.stdout + done.stderr
    return text.rstrip("\n").split("\n") if text.strip() else []


def matches(expected, actual):
    """Whether `actual` is `expected` with each … standing for any run of lines (durations masked)."""
    exp = [masked(e) for e in expected]
    act = [masked(a) for a in actual]
    parts, part = [], []
    for e in exp:
        if e.strip() == ELISION:
            parts.append(part)
            part = []
        else:
            part.append(e)
    parts.append(part)
    if len(parts) == 1:
        return exp == act
    at = 0
    for n, part in enumerate(parts):
        if n == 0:
            if act[: len(part)] != part:
                return False
            at = len(part)
            continue
        if n == len(parts) - 1:
            return len(act) - len(part) >= at and (not part or act[len(act) - len(part):] == part)
        found = next((i for i in range(at, len(act) - len(part) + 1)
                      if act[i:i + len(part)] == part), None)
        if found is None:
            return False
        at = found + len(part)
    return True


def self_test():
    """The matching rules on hand-made cases: each must decide as stated, or the check is void."""
    cases = [
        (["a", "b"], ["a", "b"], True),
        (["a", "b"], ["a", "c"], False),             # a changed line
        (["a"], ["a", "b"], False),                  # a line the docs do not show
        (["a", "b"], ["a"], False),                  # a line the program no longer prints
        (["x in 0.11 s"], ["x in 2.5 s"], True),     # durations are the machine's
        (["x 12.47"], ["x 12.48"], False),           # other numbers are not masked
        (["gears  0.5 s"], ["gears  31 s"], True),
        (["…", "c"], ["a", "b", "c"], True),         # … stands for any lines
        (["…", "c"], ["a", "b", "d"], False),
        (["a", "…", "c", "…"], ["a", "b", "c", "d", "e"], True),
        (["a", "…", "c", "…"], ["a", "b", "d", "e"], False),
        (["a", "…", "c", "…", "e"], ["a", "c", "e"], True),
        (["a", "…", "e", "…", "c"], ["a", "c", "e"], False),  # in order
    ]
    bad = [(e, a, want) for e, a, want in cases if matches(e, a) != want]
    for e, a, want in bad:
        print(f"self-test: matches({e}, {a}) should be {want}")
    print(f"self-test: {len(cases) - len(bad)} of {len(cases)} cases as stated")
    return 1 if bad else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--gearmc", help="the binary under test")
    parser.add_argument("--self-test", action="store_true", help="test the matching rules only")
    parser.add_argument("--root", default=str(pathlib.Path(__file__).resolve().parents[2]))
    parser.add_argument("--update", action="store_true")
    parser.add_argument("--timeout", type=float, default=300.0, help="seconds per command")
    parser.add_argument("files", nargs="*", help="default: README.md and docs/*.md")
    args = parser.parse_args()
    if args.self_test:
        return self_test()
    if not args.gearmc:
        parser.error("--gearmc is required")
    root = pathlib.Path(args.root).resolve()
    files = [pathlib.Path(f) for f in args.files] or [root / "README.md"] + sorted(
        (root / "docs").glob("*.md"))
    binary = pathlib.Path(args.gearmc).resolve()
    failures, checked = 0, 0
    for path in files:
        lines, found = blocks(path)
        replacements = []  # (first line, old length, new lines), applied last to first
        # Each file's blocks in one scratch folder, in order: a later block may read what an
        # earlier one wrote (a readings file), as a reader following the page would.
        with tempfile.TemporaryDirectory(prefix="gearmc-transcripts-") as scratch:
            os.makedirs(os.path.join(scratch, "build"))
            os.symlink(binary, os.path.join(scratch, "build", "gearmc"))
            os.symlink(root / "scenarios", os.path.join(scratch, "scenarios"))
            for first, block in found:
                where = f"{path.relative_to(root) if path.is_relative_to(root) else path}:{first}"
                new_block = []
                ok = True
                for command, expected in steps(block, where):
                    actual = run(command, scratch, args.timeout)
                    checked += 1
                    if not matches(expected, actual):
                        ok = False
                        if not args.update or any(e.strip() == ELISION for e in expected):
                            failures += 1
                            print(f"{where}: `{command}` prints otherwise than the docs show:")
                            sys.stdout.writelines(
                                line + "\n" for line in difflib.unified_diff(
                                    [masked(e) for e in expected], [masked(a) for a in actual],
                                    "docs", "gearmc", lineterm=""))
                        new_block += ("$ " + command).split("\n") + (expected if any(
                            e.strip() == ELISION for e in expected) else actual)
                    else:
                        new_block += ("$ " + command).split("\n") + expected
                if not ok and args.update:
                    replacements.append((first, len(block), new_block))
        for first, length, new_block in reversed(replacements):
            lines[first:first + length] = new_block
        if replacements:
            path.write_text("\n".join(lines), encoding="utf-8")
            print(f"{path}: transcripts rewritten")
    print(f"{checked} transcript commands checked, {failures} differ")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
