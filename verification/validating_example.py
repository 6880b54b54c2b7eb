#!/usr/bin/env python3
"""docs/validating.md's worked example, run for real: the independent Python candidate
(docs/examples/candidate_upright.py, closed forms in mpmath) passes `flipflux validate` against
the golden data, and a corrupted copy (one value off in its 9th digit, a missing row, a
duplicated row, a malformed line) fails with each defect reported on its line.
Usage: validating_example.py FLIPFLUX_EXECUTABLE"""
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCRIPT = os.path.join(ROOT, "docs", "examples", "candidate_upright.py")
GOLDEN = os.path.join(ROOT, "data", "golden")


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True)


def main():
    exe = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        good = os.path.join(tmp, "candidate.csv")
        with open(good, "w") as f:
            f.write(run([sys.executable, SCRIPT]).stdout)
        r = run([exe, "validate", good, "--golden", GOLDEN, "--allow-missing", "--rtol", "1e-25",
                 "--verbose"])
        print(r.stdout)
        assert r.returncode == 0, f"a correct candidate failed (status {r.returncode}): {r.stderr}"
        rows = [l for l in r.stdout.splitlines() if " ok " in f" {l} "]
        assert len(rows) >= 54, f"expected 54 matched rows, got {len(rows)}"

        lines = run([sys.executable, SCRIPT, "--corrupt"]).stdout.splitlines(keepends=True)
        out = []
        for l in lines:
            if l.startswith("omega,,9,"):
                continue  # a missing row
            if l.startswith("rate-upright,2,12,"):
                l = l.replace("rate-upright,2,12,", "rate-upright,2,12,x")  # malformed
            out.append(l)
            if l.startswith("flux-upright,2,10,"):
                out.append(l)  # a duplicated row
        bad = os.path.join(tmp, "bad.csv")
        with open(bad, "w") as f:
            f.writelines(out)
        r = run([exe, "validate", bad, "--golden", GOLDEN, "--allow-missing", "--rtol", "1e-12"])
        print(r.stdout)
        assert r.returncode == 1, f"a corrupted candidate passed (status {r.returncode})"
        text = r.stdout
        for word in ("FAIL", "duplicate", "malformed"):
            assert word in text, f"'{word}' not reported"
        # the corrupted value: rate-upright at E = 8 (line 12 of the file)
        fail = [l for l in text.splitlines() if "FAIL" in l and "rate-upright" in l]
        assert fail and " 8 " in f" {fail[0].replace(',', ' ')} ", fail
        # without --allow-missing, the dropped omega at E = 9 is reported as missing
        r = run([exe, "validate", bad, "--golden", GOLDEN])
        assert r.returncode == 1 and "missing" in r.stdout
    print("validating example: ok")


if __name__ == "__main__":
    main()
