#!/usr/bin/env python3
"""Structure-aware mutation fuzzer of every gearmc command, run as separate processes.

Each input is a seed file of tests/fuzz/corpus (scenarios, uncertainty models, readings CSV, DMIS
results, point tables with their column mappings) or a command line, mutated from a fixed seed by
mutators that know the file's structure (a YAML value, a CSV field, a DMIS number or statement, an
option's value) and by byte-level ones, then given to one command: geometry, run, check, sweep,
simulate, export-mesh, export-plan, diagnose (CSV, point table, DMIS) or uncertainty. Every run has
a time limit and an address-space cap, and is classified:

  clean rejection  exit 2, exactly one "gearmc: …" line on stderr (warnings aside), and nothing
                   left behind (no output folder or file, no temporary file in the work folder)
  accepted         exit 0 (check: 0, 1 or 3, its verdicts), outputs complete and without a
                   non-finite number (nan, inf) in any CSV, JSON or report
  crash            ended by a signal (SIGSEGV, SIGABRT, …)
  hang             still running at the time limit
  internal         exit 4 (an internal error), or any other code
  silent wrong     exit 0 with a non-finite number in an output, an output missing, or a
                   rejection that left files behind or printed a message that is not one line

The table lists these counts per command; the exit status is 1 when anything but "clean
rejection" and "accepted" was seen. Failures are saved (input, command, stderr) with --save.

  fuzz_commands.py --gearmc build/gearmc [--inputs N] [--seed S] [--timeout SEC]
                   [--memory-mb MB] [--jobs J] [--save DIR] [--only CMD,…] [--progress N]
"""
import argparse
import concurrent.futures
import json
import os
import random
import re
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
CORPUS = HERE / "corpus"

# Values at the edges of every number type and parser, as in fuzz_inputs.cpp.
SPECIAL = ["1e308", "-1e308", "1e309", "1e-320", "nan", ".nan", "NaN", "inf", ".inf", "-.inf",
           "-1", "0", "-0", "0x10", "1_000", "99999999999999999999", "2147483648", "-2147483649",
           '""', "''", "~", "null", "[]", "{}", "[1, 2]", "{a: 1}", "true", "1e300", "0.5",
           "\xff\xfe", "\xc3\x28", "\x01", "\t", "&a", "*a", "!!binary", "? x", "#", ",", ";",
           "L", "R", "1,5", "1e-300", "4294967296", "100000", "-100000"]
LONG = ["x" * 70000, "9" * 5000, "[" * 3000, "{a: " * 2000]


class Mutator:
    def __init__(self, rng):
        self.rng = rng

    def token(self):
        r = self.rng.random()
        if r < 0.05:
            return self.rng.choice(LONG)
        if r < 0.75:
            return self.rng.choice(SPECIAL)
        return str(self.rng.choice([self.rng.randint(-10, 10), self.rng.uniform(-1e6, 1e6),
                                    10 ** self.rng.randint(-30, 30)]))

    # --- structure-aware: a value of a YAML line, a field of a CSV row, a DMIS number ----
    def yaml_value(self, lines):
        idx = [i for i, l in enumerate(lines) if ":" in l and not l.lstrip().startswith("#")]
        if not idx:
            return lines
        i = self.rng.choice(idx)
        line = lines[i]
        # a value inside a flow list/map, or the scalar after the key
        nums = list(re.finditer(r"-?\d+(\.\d+)?([eE][-+]?\d+)?", line))
        if nums and self.rng.random() < 0.6:
            m = self.rng.choice(nums)
            lines[i] = line[:m.start()] + self.token() + line[m.end():]
        else:
            k = line.index(":")
            lines[i] = line[:k + 1] + " " + self.token() + "\n"
        return lines

    def number_nudge(self, lines):
        """A number moved within reason (×0.1 … ×10, ±1): inputs that mostly still load, so the
        commands run deep instead of stopping at the reader."""
        idx = [i for i, l in enumerate(lines)
               if re.search(r"\d", l) and not l.lstrip().startswith("#")]
        if not idx:
            return lines
        i = self.rng.choice(idx)
        nums = list(re.finditer(r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?(?![\w.])", lines[i]))
        if not nums:
            return lines
        m = self.rng.choice(nums)
        text = m.group(0)
        if re.fullmatch(r"-?\d+", text):
            new = str(int(text) + self.rng.choice([-1, 1, 2, -2, 10]))
        else:
            new = repr(float(text) * self.rng.choice([0.1, 0.5, 0.9, 1.1, 2.0, 10.0]))
        lines[i] = lines[i][:m.start()] + new + lines[i][m.end():]
        return lines

    def yaml_key(self, lines):
        idx = [i for i, l in enumerate(lines) if re.match(r"\s*[A-Za-z_]+:", l)]
        if not idx:
            return lines
        i = self.rng.choice(idx)
        m = re.match(r"(\s*)([A-Za-z_]+)(:.*)", lines[i], re.S)
        key = m.group(2)
        choice = self.rng.random()
        if choice < 0.4 and len(key) > 1:
            j = self.rng.randrange(len(key))
            key = key[:j] + key[j + 1:]  # a typo
        elif choice < 0.7:
            key = key + "_x"  # an unknown key
        else:
            lines.insert(i, lines[i])  # a duplicate key
            return lines
        lines[i] = m.group(1) + key + m.group(3)
        return lines

    def csv_field(self, lines, sep=","):
        idx = [i for i, l in enumerate(lines) if sep in l and not l.startswith("#")]
        if not idx:
            return lines
        i = self.rng.choice(idx)
        fields = lines[i].rstrip("\r\n").split(sep)
        f = self.rng.randrange(len(fields))
        r = self.rng.random()
        if r < 0.7:
            fields[f] = self.token()
        elif r < 0.85:
            del fields[f]
        else:
            fields.insert(f, self.token())
        lines[i] = sep.join(fields) + "\n"
        return lines

    def dmis(self, lines):
        r = self.rng.random()
        if r < 0.15:
            unit = self.rng.choice(["INCH", "MM", "CM", "FEET", "METER", "FURLONG", "", "inch"])
            lines.insert(self.rng.randrange(len(lines) + 1), "UNITS/%s,ANGDEC\n" % unit)
            return lines
        if r < 0.3:  # break a statement over lines with `$`, or join two
            i = self.rng.randrange(len(lines))
            l = lines[i]
            k = self.rng.randrange(max(1, len(l) - 1))
            lines[i] = l[:k] + "$\n" + l[k:]
            return lines
        if r < 0.45:  # a label out of the plan's form, or another tooth/flank
            i = self.rng.randrange(len(lines))
            lines[i] = re.sub(r"T(\d+)([LR])", lambda m: "T" + self.rng.choice(
                ["0", "999", "9999", "1X", m.group(1)]) + self.rng.choice(["L", "R", "Q"]),
                lines[i], count=1)
            return lines
        return self.csv_field(lines)

    # --- generic ---------------------------------------------------------------------------
    def lines_op(self, lines):
        if not lines:
            return [self.token() + "\n"]
        r = self.rng.random()
        i = self.rng.randrange(len(lines))
        if r < 0.3:
            del lines[i]
        elif r < 0.6:
            lines.insert(i, lines[i])
        elif r < 0.8:
            j = self.rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        else:
            lines[i] = lines[i][: self.rng.randrange(len(lines[i]) + 1)]
        return lines

    def bytes_op(self, text):
        b = bytearray(text.encode("utf-8", "surrogateescape"))
        if not b:
            return text
        for _ in range(self.rng.randint(1, 4)):
            i = self.rng.randrange(len(b))
            b[i] = self.rng.choice([0, 0xFF, 0x0D, 0x0A, 0x22, 0x3A, self.rng.randrange(256)])
        if self.rng.random() < 0.1:
            b = b[: self.rng.randrange(len(b))]
        return bytes(b).decode("utf-8", "surrogateescape")

    def mutate(self, text, kind):
        if self.rng.random() < 0.4:  # mild: one or two numbers nudged
            lines = text.splitlines(keepends=True)
            for _ in range(self.rng.randint(1, 2)):
                lines = self.number_nudge(lines)
            return "".join(lines)
        rounds = 1 if self.rng.random() < 0.7 else self.rng.randint(2, 3)
        for _ in range(rounds):
            lines = text.splitlines(keepends=True)
            r = self.rng.random()
            if r < 0.05:
                text = self.bytes_op(text)
                continue
            if r < 0.2:
                lines = self.lines_op(lines)
            elif kind == "yaml":
                lines = self.yaml_key(lines) if r < 0.45 else self.yaml_value(lines)
            elif kind == "dmis":
                lines = self.dmis(lines)
            elif kind == "table":
                lines = self.csv_field(lines, ";")
            else:
                lines = self.csv_field(lines)
            text = "".join(lines)
        return text


def write_bytes(path, text):
    path.write_bytes(text.encode("utf-8", "surrogateescape"))


def readings_rows(csv_text):
    """Each row of a readings CSV as (fields, p, n, E): E = c − R n, the compensated point."""
    radius = 0.5
    for line in csv_text.splitlines():
        if line.startswith("# stylus_radius_mm="):
            radius = float(line.split("=")[1])
        if line.startswith("#") or line.startswith("gear,"):
            continue
        f = line.split(",")
        p = [float(x) for x in f[6:9]]
        n = [float(x) for x in f[9:12]]
        c = [float(x) for x in f[12:15]]
        yield f, p, n, [c[k] - radius * n[k] for k in range(3)]


def readings_to_dmis(csv_text):
    """gearmc's readings CSV as a CMM's DMIS results (the reverse of engine/readings/dmis_results)."""
    out = ["DMISMN/'fuzz seed',05.3\n", "UNITS/MM,ANGDEC\n"]
    for f, p, n, e in readings_rows(csv_text):
        label = "T%03d%s_I%02d_J%02d" % (int(f[1]), f[2], int(f[3]), int(f[4]))
        out.append("F(%s)=FEAT/POINT,CART,%r,%r,%r,%r,%r,%r\n" % (label, *p, *n))
        out.append("FA(%s)=FEAT/POINT,CART,%r,%r,%r,%r,%r,%r\n" % (label, *e, *n))
    return "".join(out)


def readings_to_table(csv_text):
    """The readings as a CMM export: semicolons, decimal commas, measured point E = c − R n."""
    rows = ["Tooth;Flank;I;J;X_nom;Y_nom;Z_nom;I_vec;J_vec;K_vec;X_act;Y_act;Z_act\n"]
    for f, p, n, e in readings_rows(csv_text):
        vals = f[1:5] + [repr(x) for x in p + n + e]
        rows.append(";".join(v.replace(".", ",") for v in vals) + "\n")
    return "".join(rows)


TABLE_COLUMNS = """columns:
  tooth: Tooth
  flank: Flank
  i: I
  j: J
  nominal: {x: X_nom, y: Y_nom, z: Z_nom}
  normal: {i: I_vec, j: J_vec, k: K_vec}
  measured: {x: X_act, y: Y_act, z: Z_act}
separator: ";"
decimal: ","
unit: mm
"""


class Seeds:
    """The seed files by kind; readings made by the gearmc under test from the diagnose example."""

    def __init__(self, gearmc, work):
        self.scenario = sorted((CORPUS / "scenario").glob("*.yaml"))
        self.model = sorted((CORPUS / "model").glob("*.yaml"))
        self.model_scenario = ROOT / "scenarios" / "diagnose" / "lobing_model.yaml"
        truth = ROOT / "scenarios" / "diagnose" / "lobing_truth.yaml"
        csv = work / "seed_readings.csv"
        r = subprocess.run([gearmc, "simulate", str(truth), "--out", str(csv), "--master"],
                           capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit("fuzz_commands: cannot make the seed readings: " + r.stderr)
        text = csv.read_text()
        self.readings = [text]
        self.dmis = [readings_to_dmis(text)]
        self.table = [readings_to_table(text)]


def command_for(name, rng, mut, seeds, work, k):
    """The argv of input k for command `name`, with its input files written into `work`/k."""
    d = work / ("in%06d" % k)
    d.mkdir()
    out = d / "out"
    pick = lambda xs: rng.choice(xs)
    if name in ("geometry", "run", "check", "sweep", "simulate", "export-mesh", "export-plan"):
        scen = d / "s.yaml"
        write_bytes(scen, mut.mutate(pick(seeds.scenario).read_text(), "yaml"))
        if name == "geometry":
            return [name, str(scen)], [], d
        if name == "run":
            return [name, str(scen), "--gears", pick(["1", "2"]), "--quiet", "--out", str(out)] + \
                pick([[], ["--points"], ["--only-gear", pick(["0", "1", "-1", "99"])]]), [out], d
        if name == "check":
            claims = ("claims:\n  - {name: c, quantity: delta_rcomp.point, statistic: {quantile: "
                      "%s}, at_most_um: %s, confidence: %s}\n" % (
                          pick(["0.9", "0.5", mut.token()]), pick(["4", "1e-300", mut.token()]),
                          pick(["0.95", "0.5", mut.token()])))
            write_bytes(scen, scen.read_text(errors="surrogateescape") + "\n" + claims)
            # Few gears: a legitimately slow geometry (a small gear with a wide stylus, ~0.15 s
            # per gear) must not pass for a hang under the time limit.
            return [name, str(scen), "--max-gears", pick(["16", "32"]), "--quiet", "--out",
                    str(out)], [out], d
        if name == "sweep":
            key = pick(["stylus.radius_mm", "probing.points_along_profile", "run.gears", "seed",
                        "gear.teeth", "x.y", "probing"])
            values = ",".join(pick(["0.5", "1", "3", mut.token()]) for _ in range(pick([1, 2])))
            return [name, str(scen), "--vary", key + "=" + values, "--gears", "1", "--quiet",
                    "--out", str(out)] + pick([[], ["--statistic", pick(
                        ["delta_rcomp.point.n", "delta_rcomp.flank_max.p99", "x"])]]), [out], d
        if name == "simulate":
            f = d / "r.csv"
            return [name, str(scen), "--out", str(f), "--gears", pick(["1", "2", "0", "-1"])] + \
                pick([[], ["--master"], ["--reference-deviations"]]), [f], d
        if name == "export-mesh":
            f = d / pick(["m.stl", "m.ply", "m.obj", "m.off", "m.xyz"])
            return [name, str(scen), "--gear", pick(["0", "1", "-1"]), "--out", str(f),
                    "--profile-samples", pick(["8", "2", "0", "100"]), "--face-samples",
                    pick(["4", "2", "1"])], [f], d
        f = d / "plan.dmi"
        return [name, str(scen), "--format", pick(["dmis", "iges"]), "--out", str(f)], [f], d
    if name == "diagnose":
        model = d / "model.yaml"
        text = seeds.model_scenario.read_text()
        kind = pick(["csv", "dmis", "table"])
        if rng.random() < 0.25:
            write_bytes(model, mut.mutate(text, "yaml"))
        else:
            model.write_text(text)
        extra = []
        if kind == "csv":
            meas = d / "r.csv"
            write_bytes(meas, mut.mutate(pick(seeds.readings), "csv"))
        elif kind == "dmis":
            meas = d / "r.dmo"
            write_bytes(meas, mut.mutate(pick(seeds.dmis), "dmis"))
        else:
            meas = d / "r.txt"
            cols = d / "columns.yaml"
            if rng.random() < 0.5:
                write_bytes(meas, mut.mutate(pick(seeds.table), "table"))
                cols.write_text(TABLE_COLUMNS)
            else:
                meas.write_text(pick(seeds.table))
                write_bytes(cols, mut.mutate(TABLE_COLUMNS, "yaml"))
            extra = ["--columns", str(cols)]
        return [name, "--model", str(model), "--measured", str(meas), "--out", str(out),
                "--null-replicates", pick(["20", "0", "5"])] + extra, [out], d
    if name == "uncertainty":
        model = d / "u.yaml"
        write_bytes(model, mut.mutate(pick(seeds.model).read_text(), "yaml"))
        return [name, str(model), "--trials", pick(["2000", "20000", "10", mut.token()]),
                "--quiet", "--out", str(out)], [out], d
    raise ValueError(name)


COMMANDS = ["geometry", "run", "check", "sweep", "simulate", "export-mesh", "export-plan",
            "diagnose", "uncertainty"]
NONFINITE = re.compile(r"^\s*[-+]?(nan|inf|infinity)\s*(µm|mm|%|°)?\s*$", re.I)


def reject_constant(name):
    raise ValueError("a non-finite number " + name)


def limits(memory_mb, seconds):
    def apply():
        if memory_mb > 0:  # 0: no cap (AddressSanitizer reserves terabytes of address space)
            resource.setrlimit(resource.RLIMIT_AS, (memory_mb << 20, memory_mb << 20))
        resource.setrlimit(resource.RLIMIT_CPU, (seconds * 4, seconds * 4))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        os.setsid()
    return apply


def outputs_finite(paths):
    """The first output (file or a file of an output folder) with a non-finite number, or None."""
    files = []
    for p in paths:
        if p.is_dir():
            files += [f for f in p.rglob("*") if f.is_file()]
        elif p.exists():
            files.append(p)
    for f in files:
        text = f.read_text(errors="replace")
        if f.suffix == ".json":  # JSON has no NaN: a written one is a bug (nlohmann writes null)
            try:
                json.loads(text, parse_constant=reject_constant)
            except ValueError as e:
                return "%s: %s" % (f.name, e)
            continue
        if f.suffix == ".csv":  # a field that is a non-finite number
            rows = [line.split(",") for line in text.splitlines() if not line.startswith("#")]
            # histograms.csv: an outermost bin edge is -inf or inf by definition (formats.md)
            edges = {i for i, name in enumerate(rows[0] if rows else []) if name.startswith("bin_")}
            cells = [c for row in rows[1:] for i, c in enumerate(row) if i not in edges]
        elif f.suffix in (".html", ".xml"):  # a table cell or label that is one
            cells = re.findall(r">([^<]*)<", text)
        else:
            continue
        for c in cells:
            if NONFINITE.match(c):
                return "%s: a value '%s'" % (f.name, c.strip())
    return None


def classify(name, argv, proc, timed_out, expected, work_dir, before):
    if timed_out:
        return "hang", "no end within the time limit"
    code = proc.returncode
    if code < 0:
        return "crash", "signal %d" % -code
    errors = [l for l in proc.stderr.splitlines() if l.startswith("gearmc: ")
              and not l.startswith("gearmc: warning:")]
    left = sorted(set(os.listdir(work_dir)) - before)
    if code == 2:
        leftovers = [str(p) for p in expected if p.exists()] + left
        if leftovers:
            return "silent wrong", "rejected but left behind: " + ", ".join(leftovers[:3])
        if len(errors) != 1:
            return "silent wrong", "a rejection with %d 'gearmc:' lines" % len(errors)
        return "clean rejection", errors[0][:200]
    verdicts = (0, 1, 3) if name == "check" else (0,)
    if code in verdicts:
        missing = [str(p) for p in expected if not p.exists()]
        if missing:
            return "silent wrong", "exit %d without %s" % (code, missing[0])
        bad = outputs_finite(expected)
        if bad:
            return "silent wrong", bad
        return "accepted", ""
    return "internal", "exit %d: %s" % (code, (errors or proc.stderr.splitlines() or [""])[-1][:200])


def run_one(job):
    name, argv, expected, d, gearmc, timeout, memory_mb = job
    before = set(os.listdir(d))
    start = time.monotonic()
    try:
        proc = subprocess.run([gearmc] + argv, capture_output=True, text=True, errors="replace",
                              timeout=timeout, cwd=d, preexec_fn=limits(memory_mb, timeout))
        timed_out = False
    except subprocess.TimeoutExpired as e:
        proc, timed_out = e, True
    seconds = time.monotonic() - start
    kind, detail = classify(name, argv, proc, timed_out, expected, d, before)
    return name, argv, kind, detail, (proc.stderr or "") if not timed_out else "", d, seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gearmc", default=str(ROOT / "build" / "gearmc"))
    ap.add_argument("--inputs", type=int, default=900, help="inputs in all (spread over commands)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--timeout", type=int, default=20, help="seconds per run")
    ap.add_argument("--memory-mb", type=int, default=4096,
                    help="address-space cap per run (0: none, for sanitizer builds)")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--save", help="folder for the inputs that were not clean")
    ap.add_argument("--only", help="comma-separated commands")
    ap.add_argument("--verbose", action="store_true", help="print every run's outcome")
    ap.add_argument("--progress", type=int, default=0,
                    help="print the table so far to stderr after every N inputs")
    a = ap.parse_args()
    a.gearmc = os.path.abspath(a.gearmc)  # the runs start in their own folders
    commands = a.only.split(",") if a.only else COMMANDS
    work = Path(tempfile.mkdtemp(prefix="gearmc_fuzz_"))
    rng = random.Random(a.seed)
    mut = Mutator(rng)
    seeds = Seeds(a.gearmc, work)
    kinds = ["clean rejection", "accepted", "crash", "hang", "internal", "silent wrong"]
    table = {c: dict.fromkeys(kinds, 0) for c in commands}
    bad = []

    def jobs():
        # Made one at a time as the runs need them (the same inputs, in the same order, as when
        # made all at once): a long run needs no disk for its inputs up front.
        for k in range(a.inputs):
            name = commands[k % len(commands)]
            argv, expected, d = command_for(name, rng, mut, seeds, work, k)
            if rng.random() < 0.05:  # a mutated option value (not where the outputs go)
                i = rng.randrange(1, len(argv))
                if argv[i - 1].startswith("--") and argv[i - 1] not in ("--out", "--junit"):
                    argv[i] = mut.token()
            yield (name, argv, expected, d, a.gearmc, a.timeout, a.memory_mb)

    def table_text(done):
        lines = ["| command | inputs | " + " | ".join(kinds) + " |",
                 "|---|---:|" + "---:|" * len(kinds)]
        total = dict.fromkeys(kinds, 0)
        for c in commands:
            n = sum(table[c].values())
            lines.append("| %s | %d | " % (c, n) + " | ".join(str(table[c][k]) for k in kinds) +
                         " |")
            for k in kinds:
                total[k] += table[c][k]
        lines.append("| all | %d | " % done + " | ".join(str(total[k]) for k in kinds) + " |")
        return "\n".join(lines)

    done = 0
    slowest = []  # (seconds, command, argv) of the three longest runs that ended in time

    def finish(result):
        # Counted, saved at once when not clean (an interrupted long run keeps what it found),
        # and the input's folder removed.
        nonlocal done
        name, argv, kind, detail, stderr, d, seconds = result
        done += 1
        if kind != "hang":
            slowest.append((seconds, name, argv))
            slowest.sort(key=lambda x: -x[0])
            del slowest[3:]
        table[name][kind] += 1
        if a.verbose:
            print("%s: %s: %s" % (name, kind, detail[:160]))
        if kind not in ("clean rejection", "accepted"):
            bad.append((name, argv, kind, detail, stderr, d))
            if a.save:
                target = Path(a.save) / ("%s_%03d" % (kind.replace(" ", "_"), len(bad) - 1))
                shutil.copytree(d, target, dirs_exist_ok=True)  # the input's own folder
                (target / "command.txt").write_text(kind + ": " + detail + "\ngearmc " +
                                                    " ".join(argv) + "\n\n" + stderr)
        shutil.rmtree(d, ignore_errors=True)
        if a.progress and done % a.progress == 0:
            print("fuzz_commands: %d of %d inputs\n%s" % (done, a.inputs, table_text(done)),
                  file=sys.stderr, flush=True)

    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        pending = set()
        for job in jobs():
            pending.add(pool.submit(run_one, job))
            if len(pending) >= 2 * a.jobs:
                finished, pending = concurrent.futures.wait(
                    pending, return_when=concurrent.futures.FIRST_COMPLETED)
                for f in finished:
                    finish(f.result())
        for f in concurrent.futures.as_completed(pending):
            finish(f.result())
    print("fuzz_commands: %d inputs, seed %d, %d s and %d MB per run" % (
        a.inputs, a.seed, a.timeout, a.memory_mb))
    print(table_text(done))
    for seconds, name, argv in slowest:  # how close the longest runs came to the limit
        print("slow: %.1f s %s: gearmc %s" % (seconds, name, " ".join(
            x if len(x) < 200 else x[:60] + "…" for x in argv)))
    for name, argv, kind, detail, stderr, d in bad[:40]:
        print("%s: %s: %s\n  gearmc %s" % (kind, name, detail, " ".join(
            x if len(x) < 200 else x[:60] + "…" for x in argv)))
    shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
