#!/usr/bin/env python3
"""The Taylor ensemble against DOP853 on the same initial states: paired flip-count differences.

    paired_methods.py FLIPFLUX [--energies 2.5,3.5,4.3,5.5] [--trajectories 1000] [--time 2000]
        [--arm 2] [--taylor-rtol 1e-13] [--dop853-rtol 1e-10] [--seed 7] [--threads 2]
        > bench/results/taylor_vs_dop853.txt

Runs `FLIPFLUX simulate` twice per energy, `--method dop853` and `--method taylor`, with the same
seed (so the same initial states: the tool checks the states `--write-initial-states` writes are
identical), and compares each trajectory's flip counts per criterion. Chaos makes the two
trajectories part after a few Lyapunov times, so single counts differ; what is tested is the mean:
the paired differences d = taylor - dop853 have mean 0 when both integrators sample the same
flip-count distribution. Per (energy, criterion) it prints the mean of d, its standard error
sd/sqrt(n) over the n independent trajectories (the initial states are drawn per index), z =
mean / se, a percentile bootstrap 95 % interval of the mean (2000 resamples of the trajectories,
seeded; at n = 1000 it nearly equals the normal interval, a check that d's tails do not spoil it),
and the share of trajectories with d = 0. The criteria of one energy count the same
trajectories' flips, so their rows are not independent tests. A summary line ends the output.
"""
import argparse
import csv
import json
import math
import os
import random
import shutil
import statistics
import subprocess
import sys
import tempfile


def run(flipflux, energy, method, rtol, a, work):
    out = os.path.join(work, "%s-E%s" % (method, energy))
    states = out + "-states.csv"
    cmd = [flipflux, "simulate", "--energy", energy, "--trajectories", str(a.trajectories),
           "--time", a.time, "--arm", a.arm, "--seed", a.seed, "--method", method, "--rtol", rtol,
           "--threads", a.threads, "--csv-dir", out, "--write-initial-states", states,
           "--no-timing"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit("paired_methods.py: '%s' failed (%d): %s" % (" ".join(cmd), p.returncode,
                                                              p.stderr.strip()[-400:]))
    report = json.loads(p.stdout)
    table = os.path.join(out, "trajectories_E%s.csv" % energy)
    rows = list(csv.DictReader(open(table)))
    return report, rows, open(states).read()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("flipflux")
    ap.add_argument("--energies", default="2.5,3.5,4.3,5.5")
    ap.add_argument("--trajectories", type=int, default=1000)
    ap.add_argument("--time", default="2000")
    ap.add_argument("--arm", default="2")
    ap.add_argument("--taylor-rtol", default="1e-13")
    ap.add_argument("--dop853-rtol", default="1e-10")
    ap.add_argument("--seed", default="7")
    ap.add_argument("--threads", default="2")
    a = ap.parse_args()
    if a.trajectories < 2:
        sys.exit("paired_methods.py: --trajectories must be >= 2")
    version = subprocess.run([a.flipflux, "--version"], capture_output=True,
                             text=True).stdout.strip()
    print("# paired_methods.py %s --energies %s --trajectories %d --time %s --arm %s "
          "--taylor-rtol %s --dop853-rtol %s --seed %s" %
          (os.path.basename(a.flipflux), a.energies, a.trajectories, a.time, a.arm,
           a.taylor_rtol, a.dop853_rtol, a.seed))
    print("# %s" % version)
    print("# d = taylor flips - dop853 flips per trajectory (same initial state); se = sd(d)/sqrt(n); "
          "bootstrap: 95 % interval of mean(d), 2000 resamples")
    print("energy,criterion,n,mean_taylor,mean_dop853,mean_d,se_d,z,boot_lo,boot_hi,"
          "share_d_zero,max_abs_d")
    work = tempfile.mkdtemp(prefix="ff_paired_")
    rng = random.Random(20261129)
    zs, outside = [], 0
    for energy in a.energies.split(","):
        _, rows_d, states_d = run(a.flipflux, energy, "dop853", a.dop853_rtol, a, work)
        _, rows_t, states_t = run(a.flipflux, energy, "taylor", a.taylor_rtol, a, work)
        if states_d != states_t:
            sys.exit("paired_methods.py: E = %s: the two runs' initial states differ" % energy)
        if [r["index"] for r in rows_d] != [r["index"] for r in rows_t]:
            sys.exit("paired_methods.py: E = %s: the runs' trajectory indices differ" % energy)
        criteria = [k[len("flips_"):] for k in rows_d[0] if k.startswith("flips_")]
        for c in criteria:
            ok = [(t, d) for t, d in zip(rows_t, rows_d)
                  if t["status"] == "ok" and d["status"] == "ok"]
            ft = [int(t["flips_" + c]) for t, _ in ok]
            fd = [int(d["flips_" + c]) for _, d in ok]
            diff = [x - y for x, y in zip(ft, fd)]
            n = len(diff)
            if n < 2:
                sys.exit("paired_methods.py: E = %s, %s: fewer than 2 trajectories finished in "
                         "both runs" % (energy, c))
            mean = statistics.fmean(diff)
            se = statistics.stdev(diff) / math.sqrt(n)
            z = mean / se if se > 0 else (0.0 if mean == 0 else math.copysign(math.inf, mean))
            boots = sorted(statistics.fmean(rng.choices(diff, k=n)) for _ in range(2000))
            lo, hi = boots[49], boots[1950]
            zs.append(z)
            outside += 0 if lo <= 0 <= hi else 1
            print("%s,%s,%d,%.3f,%.3f,%.3f,%.3f,%.2f,%.3f,%.3f,%.3f,%d" %
                  (energy, c, n, statistics.fmean(ft), statistics.fmean(fd), mean, se, z, lo, hi,
                   sum(1 for x in diff if x == 0) / n, max(abs(x) for x in diff)))
            sys.stdout.flush()
    shutil.rmtree(work, ignore_errors=True)
    chi2 = sum(z * z for z in zs)
    # the criteria of one energy count the same trajectories' flips: their z are correlated, so
    # sum z^2 is compared with its cell count only as a rough scale
    print("# summary: %d cells; max |z| %.2f; sum z^2 = %.1f over %d cells (criteria of one energy "
          "correlated); bootstrap intervals without 0: %d" %
          (len(zs), max(abs(z) for z in zs), chi2, len(zs), outside))


if __name__ == "__main__":
    main()
