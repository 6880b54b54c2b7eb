"""The walkthrough's Python simulator (examples/simulator/pendulum.py) against flipflux's checks.

docs/validating.md walks a simulator author through three checks with this simulator; this test
runs each on a small workload and asserts that the correct simulator passes and the wrong one
(`--bug`: the sign of the coupling term in dl1/dt flipped) fails:

(a) trajectory check: states s01 and s03 of data/golden/trajectories over T = 40, events and
    states, `flipflux validate --trajectories EV --states ST --state sNN` exits 0;
(b) the same with --bug exits 1 and names the first differing event ("first difference: ...
    event N");
(c) paired ensemble check: flipflux samples 16 states at E = 5 (`simulate --write-initial-states`),
    the simulator integrates them over T = 10 (`ensemble --initial-states --paired`), and
    `validate --ensemble F --paired` exits 0 for the correct simulator, 1 for --bug with a "first
    difference" line naming a trajectory;
(d) unpaired ensemble check: 40 trajectories of the simulator's own sample at E = 5 over T = 20
    (seed 1): the correct simulator passes with its own variance (flips_sq) and with totals only
    (flipflux's pilot variance); --bug fails with totals only. With flips_sq the buggy
    simulator's own spread is wide (its counts scatter far more than a correct simulator's), so
    at this budget it only warns (|z| 4.2, printed, not asserted): the pilot's variance, a
    correct simulator's, is the sharper test of a wrong one (docs/validating.md).

Every step is timed and the timings printed; the workloads are small enough for a sanitizer
build (about 20 s of Python at this size). Run by ctest (tests/CMakeLists.txt): FLIPFLUX_EXE and
FLIPFLUX_SOURCE_DIR from the environment.
"""
import csv
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time

EXE = os.environ["FLIPFLUX_EXE"]
SOURCE = pathlib.Path(os.environ["FLIPFLUX_SOURCE_DIR"])
SIMULATOR = SOURCE / "examples/simulator/pendulum.py"
INITIAL_STATES = SOURCE / "data/golden/trajectories/initial_states.csv"

failures = []
timings = []


def run(label, args, cwd):
    """Runs args in cwd, times it, and returns the CompletedProcess (output as text)."""
    start = time.monotonic()
    r = subprocess.run([str(a) for a in args], capture_output=True, text=True, cwd=cwd,
                       env={**os.environ, "PYTHONDONTWRITEBYTECODE": "1"})
    seconds = time.monotonic() - start
    timings.append((label, seconds))
    print(f"[{seconds:6.2f} s] {label}: exit {r.returncode}", flush=True)
    return r


def flipflux(label, *args, cwd):
    return run(label, [EXE, *args], cwd)


def simulator(label, *args, cwd):
    """pendulum.py under this interpreter (/usr/bin/python3 from ctest: numpy and scipy)."""
    r = run(label, [sys.executable, SIMULATOR, *args], cwd)
    if r.returncode != 0:
        failures.append(f"{label}: pendulum.py failed (exit {r.returncode}): {r.stderr.strip()}")
    return r


def expect(label, r, status, pattern=None):
    """Records a failure unless r exited with status (and, given pattern, printed a matching
    line on stdout). Shows flipflux's report either way."""
    print("    " + r.stdout.strip().replace("\n", "\n    "))
    if r.stderr.strip():
        print("    stderr: " + r.stderr.strip().replace("\n", "\n    stderr: "))
    if r.returncode != status:
        failures.append(f"{label}: exit status {r.returncode}, expected {status}")
    if pattern and not re.search(pattern, r.stdout, re.MULTILINE):
        failures.append(f"{label}: no line matching '{pattern}' in its report")


def golden_state(name):
    with INITIAL_STATES.open() as f:
        for row in csv.DictReader(f):
            if row["name"] == name:
                return ",".join(row[k] for k in ("theta1", "theta2", "l1", "l2"))
    sys.exit(f"no state {name} in {INITIAL_STATES}")


def trajectory_checks(work):
    """(a) and (b)."""
    for name in ("s01", "s03"):
        state = golden_state(name)
        for bug in (False, True):
            tag = f"{name}{' --bug' if bug else ''}"
            ev, st = work / f"ev-{name}-{bug}.csv", work / f"st-{name}-{bug}.csv"
            simulator(f"(a/b) pendulum.py trajectory {tag}", "trajectory", "--state", state,
                      "--time", "40", "--events", ev, "--states", st, *(["--bug"] if bug else []),
                      cwd=work)
            r = flipflux(f"(a/b) validate --trajectories {tag}", "validate", "--trajectories", ev,
                         "--states", st, "--state", name, cwd=work)
            if bug:
                expect(f"(b) {tag}", r, 1, r"^first difference: .*event \d+")
            else:
                expect(f"(a) {tag}", r, 0, r"-> AGREE")


def paired_checks(work):
    """(c): flipflux's states, the simulator's counts trajectory by trajectory."""
    init = work / "init.csv"
    r = flipflux("(c) simulate --write-initial-states", "simulate", "--energy", "5",
                 "--trajectories", "16", "--time", "10", "--arm", "both", "--criteria", "upright",
                 "--write-initial-states", init, "--no-timing", cwd=work)
    if r.returncode != 0 or not init.exists():
        failures.append(f"(c) simulate --write-initial-states failed (exit {r.returncode}): "
                        f"{r.stderr.strip()}")
        return
    for bug in (False, True):
        tag = " --bug" if bug else ""
        out = work / f"paired-{bug}.csv"
        simulator(f"(c) pendulum.py ensemble --paired{tag}", "ensemble", "--initial-states", init,
                  "--time", "10", "--paired", "--out", out, *(["--bug"] if bug else []), cwd=work)
        r = flipflux(f"(c) validate --ensemble --paired{tag}", "validate", "--ensemble", out,
                     "--paired", cwd=work)
        if bug:
            expect(f"(c) paired{tag}", r, 1, r"first difference.*trajectory")
        else:
            expect(f"(c) paired{tag}", r, 0)


def totals_only(path, to):
    """The candidate's file without flips_sq (the pilot's variance is used)."""
    lines = path.read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    keep = [c for c, name in enumerate(lines[header].split(",")) if name != "flips_sq"]
    to.write_text("\n".join(lines[:header] + [",".join(line.split(",")[c] for c in keep)
                                              for line in lines[header:]]) + "\n")


def unpaired_checks(work):
    """(d): the simulator's own sample, rates against the prediction."""
    for bug in (False, True):
        tag = " --bug" if bug else ""
        out, totals = work / f"agg-{bug}.csv", work / f"agg-totals-{bug}.csv"
        simulator(f"(d) pendulum.py ensemble{tag}", "ensemble", "--energy", "5",
                  "--trajectories", "40", "--time", "20", "--seed", "1", "--out", out,
                  *(["--bug"] if bug else []), cwd=work)
        if not out.exists():
            return
        totals_only(out, totals)
        r = flipflux(f"(d) validate --ensemble (flips_sq){tag}", "validate", "--ensemble", out,
                     cwd=work)
        if bug:  # shown, not asserted: the buggy counts' own spread hides the bias at this size
            print("    " + r.stdout.strip().replace("\n", "\n    "))
        else:
            expect(f"(d) unpaired (flips_sq){tag}", r, 0, r"-> PASSED")
        r = flipflux(f"(d) validate --ensemble (totals, pilot 300){tag}", "validate",
                     "--ensemble", totals, "--pilot", "300", cwd=work)
        if bug:
            expect(f"(d) unpaired (totals){tag}", r, 1, r"^\S+\s+FAIL\s+upright")
        else:
            expect(f"(d) unpaired (totals){tag}", r, 0, r"-> PASSED")


def main():
    with tempfile.TemporaryDirectory() as d:
        work = pathlib.Path(d)
        trajectory_checks(work)
        paired_checks(work)
        unpaired_checks(work)
    print("\ntimings:")
    for label, seconds in timings:
        print(f"  {seconds:6.2f} s  {label}")
    print(f"  {sum(s for _, s in timings):6.2f} s  total")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
