#!/usr/bin/env python3
"""Two flipflux binaries on the same command, run alternately: CPU seconds per run and whether
their outputs are byte-identical (a change meant to be faster and give the same bits).

    python3 tools/ab_binaries.py A B [--rounds N] [--isa LIST] -- FLIPFLUX ARGS...

Runs A, B, A, B, ... N times each (alternating, so that a slow minute of a shared machine hits
both), for each instruction set in --isa (FLIPFLUX_VECTOR_ISA, comma-separated; default: the
automatic choice). Prints a header (both binaries' versions, the processor, the load), one line
per run ("isa NAME binary A|B round K user U sys S wall W"), per binary and instruction set the
median and minimum user CPU seconds, the ratio of B's median to A's, and whether every output
(stdout) of B equals A's byte for byte, the lines of the JSON keys naming the build
("git_commit": two builds of different commits) and the run's timings ("seconds",
"cpu_seconds": they differ between any two runs) left out. Exit status 1 when the outputs differ.
"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import time


def version(binary):
    r = subprocess.run([binary, "--version"], capture_output=True, text=True)
    return r.stdout.strip().splitlines()[0] if r.returncode == 0 and r.stdout else "unknown"


def processor():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def computed(out):
    """stdout without the lines naming the build (its git commit), which differ between builds,
    and the timings, which differ between runs."""
    return b"\n".join(l for l in out.split(b"\n")
                      if not re.match(rb'\s*"(git_commit|seconds|cpu_seconds)":', l))


def run_once(binary, args, isa):
    env = dict(os.environ)
    if isa != "auto":
        env["FLIPFLUX_VECTOR_ISA"] = isa
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    r = subprocess.run([binary] + args, capture_output=True, env=env)
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        sys.exit(f"ab_binaries: {binary} exited with {r.returncode}: "
                 f"{r.stderr.decode(errors='replace').strip()[:300]}")
    return (after.ru_utime - before.ru_utime, after.ru_stime - before.ru_stime, wall, r.stdout)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("a")
    p.add_argument("b")
    p.add_argument("--rounds", type=int, default=5)
    p.add_argument("--isa", default="auto")
    argv = sys.argv[1:]
    if "--" not in argv:
        sys.exit("ab_binaries: no '--' before the flipflux arguments")
    cut = argv.index("--")
    o = p.parse_args(argv[:cut])
    args = argv[cut + 1:]
    if not args:
        sys.exit("ab_binaries: no flipflux arguments after --")
    if o.rounds < 1:
        sys.exit(f"ab_binaries: --rounds {o.rounds} must be at least 1")
    for b in (o.a, o.b):
        if not os.access(b, os.X_OK):
            sys.exit(f"ab_binaries: {b} is not an executable")
    print(f"# tools/ab_binaries.py: {' '.join(args)}")
    print(f"# A = {o.a} ({version(o.a)})")
    print(f"# B = {o.b} ({version(o.b)})")
    print(f"# {processor()}; load average before {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    same = True
    for isa in o.isa.split(","):
        times = {"A": [], "B": []}
        outputs = {"A": [], "B": []}
        for k in range(1, o.rounds + 1):
            for name, binary in (("A", o.a), ("B", o.b)):
                user, sys_s, wall, out = run_once(binary, args, isa)
                times[name].append(user)
                outputs[name].append(computed(out))
                print(f"isa {isa} binary {name} round {k} user {user:.3f} sys {sys_s:.3f} "
                      f"wall {wall:.3f}", flush=True)
        identical = all(x == outputs["A"][0] for x in outputs["A"] + outputs["B"])
        same = same and identical
        med = {n: statistics.median(t) for n, t in times.items()}
        for n in ("A", "B"):
            print(f"isa {isa} binary {n}: median user {med[n]:.3f} s, min {min(times[n]):.3f} s")
        print(f"isa {isa}: B/A median user {med['B'] / med['A']:.3f}; outputs "
              f"{'identical' if identical else 'DIFFER'}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
