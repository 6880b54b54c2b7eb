#!/usr/bin/env python3
"""docs/validating.md's worked simulator, run at a size too slow for CI: the independent scipy
simulator (examples/simulator/pendulum.py, its equations pasted from `flipflux model
--equations`) passes `flipflux validate --ensemble` at E = 5.5 and 8 (100 trajectories x T = 10
each), the same simulator with its bug (--bug: the coupling term's sign in dl1/dt) fails, and with
the candidate's variance column removed the pilot's bound is used (and the verdicts stand).
CI runs the small version (tests/examples/test_python_simulator.py).
Usage: simulator_example.py FLIPFLUX_EXECUTABLE"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "examples", "simulator", "pendulum.py")
ENERGIES = ("5.5", "8")


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def candidate(tmp, name, *args):
    """The simulator's rows at every energy, in one file (one header)."""
    lines = []
    for e in ENERGIES:
        part = os.path.join(tmp, f"{name}.{e}.csv")
        r = run([sys.executable, SCRIPT, "ensemble", "--energy", e, "--trajectories", "100",
                 "--seed", "1", "--time", "10", "--out", part, *args])
        assert r.returncode == 0, r.stderr
        with open(part) as f:
            rows = [l for l in f.read().splitlines() if not l.startswith("#")]
        lines += rows if not lines else rows[1:]
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(open(path).read())
    return path


def main():
    exe = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        good = candidate(tmp, "good.csv")
        r = run([exe, "validate", "--ensemble", good])
        print(r.stdout, r.stderr)
        assert r.returncode == 0, f"the correct simulator failed (status {r.returncode})"
        assert r.stdout.startswith("summary: 4 rows: 4 pass"), r.stdout

        bad = candidate(tmp, "bad.csv", "--bug")
        r = run([exe, "validate", "--ensemble", bad])
        print(r.stdout, r.stderr)
        assert r.returncode == 1, f"the buggy simulator passed (status {r.returncode})"
        fails = [l for l in r.stdout.splitlines()[2:] if " FAIL " in l]
        assert len(fails) >= 3, f"the buggy simulator's rows should fail: {fails}"

        # without flips_sq: the pilot's variance bound (a small pilot keeps this cheap)
        for path, status in ((good, 0), (bad, 1)):
            with open(path) as f:
                rows = [l.rsplit(",", 1)[0] for l in f.read().splitlines()]
            totals = path + ".totals.csv"
            with open(totals, "w") as f:
                f.write("\n".join(rows) + "\n")
            r = run([exe, "validate", "--ensemble", totals, "--pilot", "200"])
            print(r.stdout, r.stderr)
            assert r.returncode == status, f"{totals}: status {r.returncode}, expected {status}"
            assert "pilot 200" in r.stdout
    print("simulator example: ok")


if __name__ == "__main__":
    main()
