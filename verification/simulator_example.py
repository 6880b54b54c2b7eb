#!/usr/bin/env python3
"""docs/validating.md's simulator example, run for real: the independent scipy simulator
(docs/examples/simulator_scipy.py) passes `flipflux validate --ensemble`, the same simulator with
its boundary bug (--bug: crossings within 0.1 of a segment start dropped) fails, and with the
candidate's variance column removed the pilot's bound is used (and the verdicts stand).
Usage: simulator_example.py FLIPFLUX_EXECUTABLE"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "docs", "examples", "simulator_scipy.py")


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def candidate(tmp, name, *args):
    r = run([sys.executable, SCRIPT, *args])
    assert r.returncode == 0, r.stderr
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(r.stdout)
    print(r.stdout)
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
        # ~40 % of the crossings are lost; a row fails when that is >= 5 of its standard errors
        # (the rows with ~300 flips); arm 1 at E = 5.5 (~80 flips) may only warn
        assert len(fails) >= 3, f"the buggy simulator's rows with many flips should fail: {fails}"

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
