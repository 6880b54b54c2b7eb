#!/usr/bin/env python3
"""Where a flipflux command spends its time: `perf record` of one run, the samples' shares by
symbol and summed over named groups of symbols (docs/scale.md quotes the groups).

    python3 tools/perf_groups.py PROFILE FLIPFLUX [--repeat N]

PROFILE is one of the profiles below (a command and its symbol groups). Prints a header (the
command, flipflux's version, the processor), one line per group ("group NAME: P %"), then the
symbols above 0.5 %. Needs `perf` (Debian's linux-perf) and permission to record
(kernel.perf_event_paranoid <= 2 for one's own processes). Percentages are of all samples of the
process, start-up included.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

PROFILES = {
    # the ensemble bench's workload as a command (bench/ensemble_odeint.cpp: E = 5, three arm-2
    # criteria, DOP853 at rtol 1e-10, one thread, no chaos indicator)
    "ensemble": {
        "args": ["simulate", "--energy", "5", "--criteria", "upright,approx,saddle",
                 "--trajectories", "2048", "--time", "100", "--threads", "1", "--seed", "1",
                 "--rtol", "1e-10", "--no-chaos", "--no-timing"],
        "groups": [
            ("vector stages (right-hand sides and stage sums)", r"vector_stages"),
            ("per-lane step ends (lockstep_round)", r"lockstep_round"),
            ("detectors (step tests, curves, dense output, root finding)",
             r"flip_detector|saddle_curve|sine_curve|upright_curve|hermite_range|detail::detect"
             r"|dense_adapter|toms748|pendulum_flow::operator\(\)|pendulum_flow::velocities"
             r"|sincos|__sin|__cos|introsort|cubic_critical"),
        ],
    },
    # one trajectory at quad (the golden state s13 to t = 120, upright flips)
    "trajectory-quad": {
        "args": ["trajectory", "--state", "0.5,1.0,2.0,4.435935", "--time", "120", "--criteria",
                 "upright", "--precision", "quad", "--sample-interval", "120",
                 "--out", "{tmp}/states.csv", "--events", "{tmp}/events.csv"],
        "groups": [
            ("libgcc software float128 (__multf3, __addtf3, __subtf3, __divtf3, ...)",
             r"__(mul|add|sub|div|neg|extend|trunc|fix|float|eq|ne|lt|le|gt|ge|unord)[a-z]*tf"
             r"|libgcc_s"),
        ],
    },
}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("profile", choices=sorted(PROFILES))
    ap.add_argument("flipflux")
    a = ap.parse_args()
    prof = PROFILES[a.profile]
    with tempfile.TemporaryDirectory(prefix="ff_perf_") as tmp:
        args = [x.replace("{tmp}", tmp) for x in prof["args"]]
        data = os.path.join(tmp, "perf.data")
        rec = subprocess.run(["perf", "record", "-q", "-o", data, a.flipflux] + args,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if rec.returncode != 0:
            sys.exit("perf_groups.py: perf record failed: " + rec.stderr.strip().splitlines()[-1]
                     if rec.stderr.strip() else "perf_groups.py: perf record failed")
        rep = subprocess.run(["perf", "report", "-i", data, "--no-children", "--stdio",
                              "--sort", "dso,symbol"],
                             capture_output=True, text=True, check=True).stdout
    shares = []
    for line in rep.splitlines():
        m = re.match(r"\s*([0-9.]+)%\s+(\S+)\s+\[\.\]\s+(.*)$", line)
        if m:
            shares.append((float(m.group(1)), m.group(2) + " " + m.group(3).strip()))
    if not shares:
        sys.exit("perf_groups.py: no samples in perf's report")
    version = subprocess.run([a.flipflux, "--version"], capture_output=True,
                             text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo")
                if l.startswith("model name")), "?")
    print("# tools/perf_groups.py %s flipflux: flipflux %s; %s" %
          (a.profile, " ".join(prof["args"]).replace("{tmp}", "TMP"), version))
    print("# %s; load average before %s; shares of all samples of the process" %
          (cpu, " ".join("%.2f" % x for x in os.getloadavg())))
    for name, pattern in prof["groups"]:
        total = sum(p for p, sym in shares if re.search(pattern, sym))
        print("group %s: %.1f %%" % (name, total))
    for p, sym in sorted(shares, reverse=True):
        if p >= 0.5:
            print("%6.2f %%  %s" % (p, sym[:160]))


if __name__ == "__main__":
    main()
