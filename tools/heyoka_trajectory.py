#!/usr/bin/env python3
"""One trajectory at quad and at 100 digits: flipflux against heyoka, side by side (issue 42).

    heyoka_trajectory.py FLIPFLUX [--hy-traj PATH] [--states s03,s05,...] [--time 12] [--repeat 3]
        > bench/results/heyoka_trajectory.txt
    heyoka_trajectory.py --summarize bench/results/heyoka_trajectory.txt

The measured rows are followed by a summary per precision (ranges and medians of the ratios, the
least digits): the lines docs/scale.md quotes. --summarize prints it again from a results file.

For each golden initial state (data/golden/trajectories/initial_states.csv) and each pair
  quad:   `flipflux trajectory --precision quad`   against `hy_traj --fp quad --compact` (real128)
  mp:100: `flipflux trajectory --precision mp:100` against `hy_traj --fp mp --prec 333` (333 bits)
both programs integrate the state to t = T and report the upright flips of both arms (flipflux
`--criteria upright`, the only events hy_traj detects) and the state at T. The runs are
interleaved, REPEAT times each; CPU seconds (user + system of the child process, from
getrusage) are medians. heyoka's own stderr splits its time into the JIT compilation and the
integration; both are printed.

"digits" is the agreement of the two programs: -log10 of the largest relative difference of the
event times and of the state at T. Agreement to D digits shows both are right to about D digits
(two independent Taylor implementations, one LLVM-compiled with its own error control).
"""
import argparse
import csv
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
from decimal import Decimal, getcontext

getcontext().prec = 400
HERE = os.path.dirname(os.path.abspath(__file__))
INITIAL = os.path.join(HERE, "..", "data", "golden", "trajectories", "initial_states.csv")
HEADER = ("state,precision,flipflux_cpu_s,heyoka_cpu_s,heyoka_jit_s,heyoka_integrate_s,"
          "ratio_whole,ratio_integrating,events,event_digits,state_digits")
PAIRS = [("quad", ["--precision", "quad"], ["--fp", "quad", "--compact"]),
         ("mp:100", ["--precision", "mp:100"], ["--fp", "mp", "--prec", "333"])]
# the digits each pair prints: agreement is capped there (identical strings agree to all of them)
PRINTED = {"quad": Decimal(36), "mp:100": Decimal(102)}


def cpu_run(cmd):
    """Runs cmd; returns (CPU seconds of the child, stdout, stderr)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        sys.exit("heyoka_trajectory.py: '%s' failed (%d): %s" % (" ".join(cmd), p.returncode,
                                                                 p.stderr.strip()[-400:]))
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, p.stdout, p.stderr


def rows(path_or_text, is_text=False):
    text = path_or_text if is_text else open(path_or_text).read()
    lines = [l for l in text.splitlines() if l and not l.startswith("#")]
    return list(csv.DictReader(lines))


def agreement(a, b):
    """Digits to which the decimal strings a and b agree (relative)."""
    x, y = Decimal(a), Decimal(b)
    if x == y:
        return Decimal(400)
    scale = max(abs(x), abs(y))
    return -((abs(x - y) / scale).log10())


def heyoka_field(stderr, name):
    for token in stderr.split():
        if token.startswith(name + "="):
            return float(token.split("=", 1)[1])
    sys.exit("heyoka_trajectory.py: hy_traj printed no %s" % name)


def summary(lines):
    """The '# summary' lines of result rows (CSV text lines with the header above)."""
    table = list(csv.DictReader(l for l in lines if l.strip() and not l.startswith("#")))
    out = []
    for label, _, _ in PAIRS:
        rs = [r for r in table if r["precision"] == label]
        if not rs:
            continue
        col = lambda k: [float(r[k]) for r in rs]
        whole, integrating = col("ratio_whole"), col("ratio_integrating")
        out.append("# summary %s: %d states; ratio whole process %.2f-%.2f (median %.2f); "
                   "ratio JIT excluded %.2f-%.2f (median %.2f), below 1 (as printed) at %d; "
                   "least event digits %.1f, least state digits %.1f" %
                   (label, len(rs), min(whole), max(whole), statistics.median(whole),
                    min(integrating), max(integrating), statistics.median(integrating),
                    sum(1 for x in integrating if x < 0.995), min(col("event_digits")),
                    min(col("state_digits"))))
    return out


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--summarize":
        for line in summary(open(sys.argv[2]).read().splitlines()):
            print(line)
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("flipflux")
    ap.add_argument("--hy-traj", default=os.environ.get("HY_TRAJ", "/tmp/heyoka-peer/hy_traj"))
    ap.add_argument("--states", default="s03,s05,s08")
    ap.add_argument("--time", default="12")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    if a.repeat < 1:
        sys.exit("heyoka_trajectory.py: --repeat must be >= 1")
    initial = {r["name"]: r for r in rows(INITIAL)}
    for s in a.states.split(","):
        if s not in initial:
            sys.exit("heyoka_trajectory.py: --states: '%s' is not a golden initial state" % s)
    version = subprocess.run([a.flipflux, "--version"], capture_output=True,
                             text=True).stdout.strip()
    cpu_model = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                      if l.startswith("model name")), platform.processor())
    print("# heyoka_trajectory.py %s --states %s --time %s --repeat %d" %
          (os.path.basename(a.flipflux), a.states, a.time, a.repeat))
    print("# %s; %s; load average before %s" %
          (version, cpu_model, " ".join("%.2f" % x for x in os.getloadavg())))
    print("# CPU seconds (user + system), medians of %d interleaved runs; heyoka split as "
          "JIT + integration" % a.repeat)
    print(HEADER)
    work = tempfile.mkdtemp(prefix="ff_hy_")
    measured = [HEADER]
    for name in a.states.split(","):
        r = initial[name]
        state = ",".join([r["theta1"], r["theta2"], r["l1"], r["l2"]])
        for label, ff_args, hy_args in PAIRS:
            ff_events = os.path.join(work, "ff_events.csv")
            ff_states = os.path.join(work, "ff_states.csv")
            hy_states = os.path.join(work, "hy_states.csv")
            ff_cmd = [a.flipflux, "trajectory", "--state", state, "--time", a.time,
                      "--criteria", "upright", "--events", ff_events, "--out", ff_states,
                      "--sample-interval", a.time] + ff_args
            hy_cmd = [a.hy_traj, "--state", state, "--time", a.time, "--sample", a.time,
                      "--state-out", hy_states] + hy_args
            ff_cpu, hy_cpu, hy_jit, hy_int = [], [], [], []
            for _ in range(a.repeat):
                c, _, _ = cpu_run(ff_cmd)
                ff_cpu.append(c)
                c, hy_out, hy_err = cpu_run(hy_cmd)
                hy_cpu.append(c)
                hy_jit.append(heyoka_field(hy_err, "jit_cpu_s"))
                hy_int.append(heyoka_field(hy_err, "integrate_cpu_s"))
            fe = [e for e in rows(ff_events) if e["criterion"] == "upright"]
            he = rows(hy_out, is_text=True)
            if [(e["arm"], e["direction"]) for e in fe] != [(e["arm"], e["direction"]) for e in he]:
                sys.exit("heyoka_trajectory.py: %s %s: the programs' flip sequences differ "
                         "(%d and %d events)" % (name, label, len(fe), len(he)))
            event_digits = min((agreement(x["time"], y["time"]) for x, y in zip(fe, he)),
                               default=Decimal(400))
            fs = [s for s in rows(ff_states) if Decimal(s["t"]) == Decimal(a.time)]
            # hy_traj writes the sample at T and its final state, the same row twice
            hs = [s for s in rows(hy_states) if Decimal(s["t"]) == Decimal(a.time)][:1]
            if len(fs) != 1 or len(hs) != 1:
                sys.exit("heyoka_trajectory.py: %s %s: no single state at t = %s" %
                         (name, label, a.time))
            state_digits = min(agreement(fs[0][k], hs[0][k])
                               for k in ("theta1", "theta2", "l1", "l2"))
            f, h = statistics.median(ff_cpu), statistics.median(hy_cpu)
            i = statistics.median(hy_int)
            row = "%s,%s,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%d,%.1f,%.1f" % (
                name, label, f, h, statistics.median(hy_jit), i, h / f, i / f, len(fe),
                min(event_digits, PRINTED[label]), min(state_digits, PRINTED[label]))
            print(row)
            sys.stdout.flush()
            measured.append(row)
    shutil.rmtree(work, ignore_errors=True)
    for line in summary(measured):
        print(line)


if __name__ == "__main__":
    main()
