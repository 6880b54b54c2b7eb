#!/usr/bin/env python3
"""The accuracy of an ensemble integrator setting, measured on the golden trajectories: each of the
13 golden states (data/golden/trajectories: 50 digits, two independent routes) integrated to t = 10
at double, the state error there (max over theta1, theta2, l1, l2, angles as integrated) against the
50-digit reference; prints the median and the maximum over the states, and every state's error.

    accuracy_levels.py FLIPFLUX [--flipflux METHOD:RTOL[:ORDER] ...] [--heyoka TOL ...]
                      [--hy-traj PATH]

--flipflux runs `flipflux trajectory --route ensemble --method METHOD --rtol RTOL` (the ensemble's
integrator, one lane; with ORDER, `--taylor-order ORDER`: the automatic order otherwise); --heyoka runs the peer's hy_traj (../shared/peers/heyoka, built by its
build.sh into /tmp/heyoka-peer) at tolerance TOL. docs/scale.md ("Against heyoka") matches the
levels of ../shared/peers/heyoka/bench.sh by these numbers: a flipflux rtol is a level's when
both its median and its maximum are at most heyoka's at the level's tolerance.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile
from decimal import Decimal

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.join(HERE, "..", "data", "golden", "trajectories")
KEYS = ("theta1", "theta2", "l1", "l2")


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#") and line.strip()))


def reference():
    """{name: (initial state text, reference state at t = 10 as Decimals)}"""
    initial = {r["name"]: ",".join(r[k] for k in KEYS) for r in rows(os.path.join(GOLDEN, "initial_states.csv"))}
    out = {}
    for r in rows(os.path.join(GOLDEN, "states.csv")):
        if Decimal(r["t"]) == 10:
            out[r["state"]] = (initial[r["state"]], [Decimal(r[k]) for k in KEYS])
    if len(out) != len(initial):
        sys.exit("accuracy_levels.py: a golden state has no sample at t = 10")
    return out


def flipflux_state(exe, state, method, rtol, order, work):
    path = os.path.join(work, "states.csv")
    r = subprocess.run([exe, "trajectory", "--state", state, "--time", "10", "--route", "ensemble",
                        "--method", method, "--rtol", rtol, "--out", path, "--sample-interval", "10"]
                       + (["--taylor-order", order] if order else []),
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"flipflux trajectory --method {method} --rtol {rtol}: {r.stderr.strip()}")
    last = [x for x in rows(path) if Decimal(x["t"]) == 10][-1]
    return [Decimal(last[k]) for k in KEYS]


def heyoka_state(exe, state, tol, work):
    path = os.path.join(work, "hy.csv")
    r = subprocess.run([exe, "--state", state, "--time", "10", "--tol", tol, "--state-out", path,
                        "--sample", "10", "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"hy_traj --tol {tol}: {r.stderr.strip()}")
    with open(path) as f:
        line = [x for x in f if x[:1].isdigit()][-1].strip().split(",")
    return [Decimal(v) for v in line[1:5]]


def summary(label, errors):
    e = sorted(errors.values())
    per = " ".join(f"{k}={float(v):.1e}" for k, v in sorted(errors.items()))
    print(f"{label}: median {float(e[len(e) // 2]):.2g} max {float(e[-1]):.2g}  [{per}]")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("flipflux")
    p.add_argument("--flipflux", dest="settings", action="append", default=[],
                   help="METHOD:RTOL or taylor:RTOL:ORDER, e.g. taylor:1e-12")
    p.add_argument("--heyoka", action="append", default=[], help="hy_traj tolerance")
    p.add_argument("--hy-traj", default="/tmp/heyoka-peer/hy_traj")
    a = p.parse_args()
    ref = reference()
    with tempfile.TemporaryDirectory() as work:
        for setting in a.settings:
            method, _, rest = setting.partition(":")
            rtol, _, order = rest.partition(":")
            errors = {n: max(abs(x - y) for x, y in zip(flipflux_state(a.flipflux, s, method, rtol, order, work), want))
                      for n, (s, want) in ref.items()}
            summary(f"flipflux {method} rtol {rtol}" + (f" order {order}" if order else ""), errors)
        for tol in a.heyoka:
            errors = {n: max(abs(x - y) for x, y in zip(heyoka_state(a.hy_traj, s, tol, work), want))
                      for n, (s, want) in ref.items()}
            summary(f"heyoka tol {tol}", errors)


if __name__ == "__main__":
    main()
