#!/usr/bin/env python3
"""Reference trajectories for validating simulators (data/golden/trajectories/, issue 15).

For every initial state of initial_states.csv, runs `flipflux trajectory` at a low and a high
precision (default mp:50 by the Gauss-Legendre reference route, events polished to full
precision, and mp:100 by the Taylor route: two precisions and two integrators) over T = 40 with
every criterion (upright, approx, saddle) of both arms, and writes

  events.csv  state,time,arm,criterion,direction,digits   (time from the high precision)
  states.csv  state,t,theta1,theta2,l1,l2,digits          (t = 10, 20, 40; high precision)

where digits = floor(-log10 |low - high| / max(|high|, 1)) (capped at the low precision's digits):
the decimal digits certified by the agreement of the two precisions (absolute for values below 1:
the event time and the state components are O(1)..O(40)); each value is the high precision's,
rounded to those digits. The two runs must list the same events
(arm, criterion, direction, in order) or the script stops. Raw outputs are cached in --work so an
interrupted run resumes; run it niced, one trajectory at a time.

The executable must be a build of a committed tree (its --version names a clean commit, not
"-dirty"), so that provenance.json names the code that computed the data; --allow-dirty overrides
for trials. events.csv and states.csv start with the pendulum's `# pendulum:` line (the candidate
header that `flipflux validate` reads, docs/validating.md).

    python3 tools/golden_trajectories.py --flipflux build/release/flipflux \
        --dir data/golden/trajectories [--low mp:50] [--high mp:100] [--work DIR] [--only s01,s02]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time
from decimal import Decimal, getcontext

getcontext().prec = 200
TIME = "40"
SAMPLES = ("10", "20", "40")
CRITERIA = "upright,approx,saddle"
PENDULUM = "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1\n"  # the paper's; the states assume it


def run(flipflux, state, precision, route, work):
    tag = f"{state['name']}-{precision.replace(':', '')}-{route}"
    events, states = os.path.join(work, tag + "-events.csv"), os.path.join(work, tag + "-states.csv")
    if not (os.path.exists(events) and os.path.exists(states)):
        st = ",".join(state[k] for k in ("theta1", "theta2", "l1", "l2"))
        t0 = time.time()
        subprocess.run([flipflux, "trajectory", "--state", st, "--time", TIME, "--precision",
                        precision, "--criteria", CRITERIA, "--arm", "both", "--sample-interval",
                        "10", "--route", route, "--events", events + ".tmp", "--out",
                        states + ".tmp"],
                       check=True, stderr=subprocess.DEVNULL)
        os.replace(events + ".tmp", events)
        os.replace(states + ".tmp", states)
        with open(os.path.join(work, tag + ".seconds"), "w") as f:
            f.write(f"{time.time() - t0:.1f}\n")
        print(f"{tag}: {time.time() - t0:.1f} s", file=sys.stderr, flush=True)
    with open(events) as f:
        ev = list(csv.DictReader(f))
    with open(states) as f:
        sts = list(csv.DictReader(f))
    return ev, sts


def seconds(work, state, precision, route):
    """The wall time of one run, as recorded when it ran (None for runs older than the record)."""
    path = os.path.join(work, f"{state['name']}-{precision.replace(':', '')}-{route}.seconds")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return float(f.read())


def digits(low, high, cap):
    a, b = Decimal(low), Decimal(high)
    if a == b:
        return cap
    d = abs(a - b) / max(abs(b), Decimal(1))
    return min(cap, int((-d.log10()).to_integral_value(rounding="ROUND_FLOOR")))


def rounded(text, d):
    """The high-precision value rounded to its certified digits (absolute below 1, relative above)."""
    b = Decimal(text)
    scale = max(abs(b), Decimal(1))
    e = -d + int(scale.log10().to_integral_value(rounding="ROUND_FLOOR"))
    return str(b.quantize(Decimal(1).scaleb(e)))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--flipflux", required=True)
    p.add_argument("--dir", default="data/golden/trajectories")
    p.add_argument("--low", default="mp:50")
    p.add_argument("--high", default="mp:100")
    p.add_argument("--low-route", default="reference", help="trajectory --route of the low precision")
    p.add_argument("--high-route", default="taylor", help="trajectory --route of the high precision")
    p.add_argument("--work", default="golden_trajectories_work")
    p.add_argument("--only", default="")
    p.add_argument("--cached-only", action="store_true",
                   help="assemble the states whose two runs are in --work; run nothing")
    p.add_argument("--allow-dirty", action="store_true",
                   help="accept an executable built from a tree with uncommitted changes")
    a = p.parse_args()
    version = subprocess.run([a.flipflux, "--version"], capture_output=True, text=True).stdout.strip()
    if "dirty" in version and not a.allow_dirty:
        sys.exit(f"{a.flipflux} is a build of a tree with uncommitted changes ({version}): commit, "
                 "rebuild, and run again (or --allow-dirty for a trial)")
    os.makedirs(a.work, exist_ok=True)
    with open(os.path.join(a.dir, "initial_states.csv")) as f:
        states = [s for s in csv.DictReader(f) if not a.only or s["name"] in a.only.split(",")]
    if a.cached_only:
        done = lambda s, p, r: os.path.exists(
            os.path.join(a.work, f"{s['name']}-{p.replace(':', '')}-{r}-states.csv"))
        states = [s for s in states if done(s, a.low, a.low_route) and done(s, a.high, a.high_route)]
    cap = int(a.low.split(":")[1])
    ev_rows, st_rows = [], []
    for s in states:
        lo_ev, lo_st = run(a.flipflux, s, a.low, a.low_route, a.work)
        hi_ev, hi_st = run(a.flipflux, s, a.high, a.high_route, a.work)
        key = lambda e: (e["arm"], e["criterion"], e["direction"])
        if [key(e) for e in lo_ev] != [key(e) for e in hi_ev]:
            sys.exit(f"{s['name']}: the events differ between {a.low} and {a.high}")
        for lo, hi in zip(lo_ev, hi_ev):
            d = digits(lo["time"], hi["time"], cap)
            ev_rows.append([s["name"], rounded(hi["time"], d), hi["arm"], hi["criterion"],
                            hi["direction"], d])
        for lo, hi in zip(lo_st, hi_st):
            if hi["t"] not in SAMPLES:
                continue
            cols = ("theta1", "theta2", "l1", "l2")
            d = min(digits(lo[c], hi[c], cap) for c in cols)
            st_rows.append([s["name"], hi["t"]] + [rounded(hi[c], d) for c in cols] + [d])
    with open(os.path.join(a.dir, "events.csv"), "w", newline="") as f:
        f.write(PENDULUM)
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["state", "time", "arm", "criterion", "direction", "digits"])
        w.writerows(ev_rows)
    with open(os.path.join(a.dir, "states.csv"), "w", newline="") as f:
        f.write(PENDULUM)
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["state", "t", "theta1", "theta2", "l1", "l2", "digits"])
        w.writerows(st_rows)
    commit = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    with open(os.path.join(a.dir, "provenance.json"), "w") as f:
        json.dump({"command": " ".join(sys.argv), "repository_commit": commit, "low": a.low, "high": a.high,
                   "time": TIME, "criteria": CRITERIA, "arms": "both",
                   "states": [s["name"] for s in states],
                   "low_route": a.low_route, "high_route": a.high_route,
                   "seconds_wall": {s["name"]: {p: seconds(a.work, s, p, r)
                                                for p, r in ((a.low, a.low_route), (a.high, a.high_route))}
                                    for s in states},
                   "flipflux_executable": a.flipflux,
                   "flipflux_version": version}, f, indent=2)
        f.write("\n")
    print(f"{len(ev_rows)} events, {len(st_rows)} states; min digits: events "
          f"{min((r[-1] for r in ev_rows), default=None)}, states {min(r[-1] for r in st_rows)}")


if __name__ == "__main__":
    main()
