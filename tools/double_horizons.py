#!/usr/bin/env python3
"""The double horizons of the reference trajectories (data/golden/trajectories/, issue 44).

A correct simulator in double precision agrees with the 50-digit reference events only up to a
time: its rounding and truncation errors (~1e-16 .. 1e-12 per unit time) grow with the
trajectory's sensitivity to its initial state, exponentially in the chaotic states. For each
reference trajectory and each offered time tolerance this script measures that time from the
reference's own error growth: it integrates the initial state at double by independent routes of
flipflux (the Taylor route, at the double limit, and DOP853 and DOPRI5 at rtol 1e-12, a tight
tolerance a careful simulator uses) and records where each parts from the reference:

  parting(run, tol) = min(the time of the first event that differs from the reference by more
                     than tol (or in direction, or is missing / extra),
                     the first sample time t in {10, 20, 40} whose state differs by more than tol)

for two accuracy classes of simulator: `limit` (at the double limit: the Taylor run alone) and
`rtol-1e-12` (min over all three runs: a simulator at rtol 1e-12 or better). Events before the
horizon agree within tol in every run of the class. It writes

  double_horizons.csv  state,time_tolerance,accuracy,horizon,parted_by
                       (horizon 40: no run parted within the reference's T = 40)

and the table between the `double-horizons` markers of README.md. `flipflux validate
--trajectories --state NAME` uses it as the default comparison horizon for a candidate whose
times are plainly double precision (at most 17 significant digits), and says whether a
difference falls before the horizon (a bug) or after it (chaos).

    python3 tools/double_horizons.py --flipflux build/release/flipflux \
        [--dir data/golden/trajectories]
"""
import argparse
import csv
import io
import os
import subprocess
import sys
from decimal import Decimal

TOLERANCES = ("1e-6", "1e-9", "1e-12")
CLASSES = {"rtol-1e-12": ("taylor", "dop853-1e-12", "dopri5-1e-12"), "limit": ("taylor",)}
RUNS = {  # name -> flipflux trajectory options (all at double)
    "taylor": ["--route", "taylor"],
    "dop853-1e-12": ["--route", "ensemble", "--method", "dop853", "--rtol", "1e-12"],
    "dopri5-1e-12": ["--route", "ensemble", "--method", "dopri5", "--rtol", "1e-12"],
}
SAMPLES = ("10", "20", "40")
BEGIN, END = "<!-- double-horizons:begin -->", "<!-- double-horizons:end -->"


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def trajectory(flipflux, state, time, options, work):
    states = os.path.join(work, "states.csv")
    r = subprocess.run([flipflux, "trajectory", "--state", state, "--time", time,
                        "--precision", "double", "--criteria", "upright,approx,saddle",
                        "--out", states, "--sample-interval", "10", *options],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"flipflux trajectory --state {state} {' '.join(options)}: {r.stderr}")
    return list(csv.DictReader(io.StringIO(r.stdout))), rows(states)


def parting(events, states, ref_events, ref_states, tol, horizon):
    """The earliest time at which the run parts from the reference at tolerance tol."""
    parted = Decimal(horizon)
    streams = {}
    for e in ref_events:
        streams.setdefault((e["arm"], e["criterion"]), [[], []])[1].append(e)
    for e in events:
        streams.setdefault((e["arm"], e["criterion"]), [[], []])[0].append(e)
    for run, ref in streams.values():
        for k in range(max(len(run), len(ref))):
            a = run[k] if k < len(run) else None
            b = ref[k] if k < len(ref) else None
            if a and b and a["direction"] == b["direction"] and \
                    abs(Decimal(a["time"]) - Decimal(b["time"])) <= tol:
                continue
            parted = min(parted, min(Decimal(x["time"]) for x in (a, b) if x))
            break
    by_t = {Decimal(s["t"]): s for s in states}
    for s in ref_states:
        t = Decimal(s["t"])
        if t not in by_t:
            sys.exit(f"no double state at t = {t}")
        if max(abs(Decimal(by_t[t][k]) - Decimal(s[k]))
               for k in ("theta1", "theta2", "l1", "l2")) > tol:
            parted = min(parted, t)
            break
    return parted


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--flipflux", required=True)
    p.add_argument("--dir", default="data/golden/trajectories")
    p.add_argument("--work", default=None, help="scratch folder (default: a temporary one)")
    a = p.parse_args()
    import json
    import tempfile
    horizon = json.load(open(os.path.join(a.dir, "provenance.json")))["time"]
    initial = rows(os.path.join(a.dir, "initial_states.csv"))
    ref_events, ref_states = rows(os.path.join(a.dir, "events.csv")), rows(
        os.path.join(a.dir, "states.csv"))
    out = []
    with tempfile.TemporaryDirectory() as scratch:
        work = a.work or scratch
        for s in initial:
            name = s["name"]
            state = ",".join(s[k] for k in ("theta1", "theta2", "l1", "l2"))
            ev = [e for e in ref_events if e["state"] == name]
            st = [x for x in ref_states if x["state"] == name]
            runs = {r: trajectory(a.flipflux, state, horizon, o, work) for r, o in RUNS.items()}
            for tol in TOLERANCES:
                part = {r: parting(e, x, ev, st, Decimal(tol), horizon)
                        for r, (e, x) in runs.items()}
                for cls, members in CLASSES.items():
                    h = min(part[r] for r in members)
                    by = ",".join(r for r in members if part[r] == h) \
                        if h < Decimal(horizon) else ""
                    out.append({"state": name, "time_tolerance": tol, "accuracy": cls,
                                "horizon": str(h), "parted_by": by})
            print(name, [(o["time_tolerance"], o["accuracy"], o["horizon"]) for o in out[-6:]],
                  file=sys.stderr)
    version = subprocess.run([a.flipflux, "--version"], capture_output=True,
                             text=True).stdout.strip()
    with open(os.path.join(a.dir, "double_horizons.csv"), "w", newline="") as f:
        f.write(f"# generated by tools/double_horizons.py with {version}\n")
        w = csv.DictWriter(f, ["state", "time_tolerance", "accuracy", "horizon", "parted_by"],
                           lineterminator="\n")
        w.writeheader()
        w.writerows(out)
    cols = [(t, c) for t in TOLERANCES for c in CLASSES]
    table = ["| state | " + " | ".join(f"{t}, {c}" for t, c in cols) + " |",
             "|---|" + "---|" * len(cols)]
    for s in initial:
        hs = {(o["time_tolerance"], o["accuracy"]): o for o in out if o["state"] == s["name"]}
        cells = [f"{float(hs[k]['horizon']):.4g}" for k in cols]
        table.append(f"| {s['name']} | " + " | ".join(cells) + " |")
    block = (BEGIN + "\n" + "\n".join(table) + "\n\nHorizons in time units (4 digits; every digit in `double_horizons.csv`, "
             "with the run that parted first), per time tolerance and accuracy class; generated "
             f"by `tools/double_horizons.py` with {version}.\n" + END)
    readme = os.path.join(a.dir, "README.md")
    text = open(readme).read()
    if BEGIN not in text or END not in text:
        sys.exit(f"{readme}: no {BEGIN} ... {END} block")
    head, rest = text.split(BEGIN, 1)
    open(readme, "w").write(head + block + rest.split(END, 1)[1])


if __name__ == "__main__":
    main()
