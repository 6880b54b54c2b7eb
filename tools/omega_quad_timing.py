#!/usr/bin/env python3
"""Omega(E) at quad: CPU seconds of one evaluation and its digits, over energies and pendulums.

    omega_quad_timing.py FLIPFLUX [--repeat N] [--baseline OTHER] > bench/results/omega_quad.txt

Each row runs `FLIPFLUX eval omega --precision quad` N times (the median of the JSON's "seconds",
the evaluation's own CPU time, process start-up excluded) and once at mp:50 as the reference;
"error" is |quad - mp:50|, "estimate" the quad run's error estimate and "ratio" estimate / error
(issue 42: the estimate within 100x of the error). --baseline: another flipflux build (e.g. one
before a change) timed in the same run, interleaved row by row, and the ratio of the medians.
The pendulums with a heavier second arm (|m| = C^2/D0 from 4 to 2^21, the cross-check's pendulum
E last) run at the same fractions of their E_max as ENERGIES are of the paper's (E_max = 6).
"""
import argparse
import json
import platform
import statistics
import subprocess
import sys
from decimal import Decimal, getcontext, localcontext

getcontext().prec = 60

PENDULUMS = {
    "paper": [],
    "light first link (m1 0.1)": ["--m1", "0.1"],
    "rigid links (a 0.5, I 1/12)": ["--a1", "0.5", "--a2", "0.5", "--I1", "0.0833333333333333333",
                                    "--I2", "0.0833333333333333333"],
}
ENERGIES = ["0.5", "1", "1.9", "2.05", "2.5", "3", "3.5", "3.9", "4.05", "4.3", "5", "5.5", "5.9"]
# at ENERGIES / 6 of their own E_max
SCALED = {
    "heavy second arm (m2 4)": ["--m2", "4"],
    "heavy second arm (m2 100)": ["--m2", "100"],
    "heavy second arm (m2 10000)": ["--m2", "10000"],
    "pendulum E (m2 2^20, rigid first link)": ["--m1", "1", "--m2", "1048576", "--L1", "0.5",
                                               "--a1", "0.25", "--I1", "0.0625", "--L2", "2",
                                               "--g", "0.0009765625"],
}


def energies_of(flipflux, model):
    """ENERGIES / 6 of the pendulum's E_max, as 12-digit decimals."""
    out = subprocess.run([flipflux, "model"] + model, check=True, capture_output=True,
                         text=True).stdout
    e_max = max(Decimal(c["energy"]) for c in json.loads(out)["critical_points"])
    out = []
    for E in ENERGIES:
        with localcontext() as c:
            c.prec = 12
            out.append(f"{(+(Decimal(E) / 6 * e_max)).normalize():f}")
    return out


def run(flipflux, energy, precision, model):
    out = subprocess.run([flipflux, "eval", "omega", "--energy", energy, "--precision", precision]
                         + model, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("flipflux")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--baseline", default=None)
    args = ap.parse_args()
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True).stdout.strip()
    print(f"# omega at quad, {args.flipflux} (commit {commit}), {platform.processor() or platform.machine()}")
    if args.baseline:
        base = subprocess.run([args.baseline, "--version"], capture_output=True, text=True).stdout
        print("# baseline: %s (%s)" % (args.baseline, base.strip().replace("\n", " ")))
    print("# pendulum | E | median CPU ms | value | error | estimate | ratio" +
          (" | baseline median CPU ms | baseline / this" if args.baseline else ""))
    rows = [(name, model, ENERGIES) for name, model in PENDULUMS.items()]
    rows += [(name, model, energies_of(args.flipflux, model)) for name, model in SCALED.items()]
    for name, model, energies in rows:
        for E in energies:
            times, base = [], []
            for _ in range(args.repeat):
                r = run(args.flipflux, E, "quad", model)
                times.append(r["seconds"])
                if args.baseline:
                    base.append(run(args.baseline, E, "quad", model)["seconds"])
            ref = run(args.flipflux, E, "mp:50", model)
            err = abs(Decimal(r["value"]) - Decimal(ref["value"]))
            est = Decimal(r["error_estimate"])
            ratio = f"{est / err:.1f}" if err > 0 else "exact"
            extra = ""
            if args.baseline:
                b, t = statistics.median(base), statistics.median(times)
                extra = f" | {1e3 * b:.1f} | {b / t:.2f}"
            print(f"{name} | {E} | {1e3 * statistics.median(times):.1f} | {r['value']} | "
                  f"{float(err):.2e} | {float(est):.2e} | {ratio}{extra}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
