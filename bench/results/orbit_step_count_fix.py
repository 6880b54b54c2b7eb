# Saddle orbits before and after the step-count fix (2026-11-30, fifteenth session): pendulums
# whose continuation chose far too few Gauss-Legendre steps (steps_for_tolerance took coarse runs
# that agreed with each other for converged). For each case `eval period`, `eval action` and
# `eval multiplier` with each binary; "multiple" is T_before / T_after where both exist (one per
# earlier binary).
#   python3 bench/results/orbit_step_count_fix.py BEFORE... AFTER > bench/results/orbit_step_count_fix.txt
import json, subprocess, sys
BEFORE, A = sys.argv[1:-1], sys.argv[-1]
def ver(ff):
    return subprocess.run([ff, "--version"], capture_output=True, text=True).stdout.strip()
print("# bench/results/orbit_step_count_fix.py: " + ", ".join(f"before{i + 1} = {ver(b)}" for i, b in enumerate(BEFORE)) + f", after = {ver(A)}")
L1 = "--m1 0.1 --m2 10 --L1 5 --L2 1 --a1 2.5 --a2 0.5 --I1 0 --I2 0.0003 --g 20".split()
L02 = "--m1 0.1 --m2 10 --L1 5 --L2 0.2 --a1 2.5 --a2 0.1 --I1 0 --I2 0.0003 --g 20".split()
HEAVY = "--m1 0.1793 --m2 31.6 --L1 0.44 --L2 0.868 --g 9.81".split()
M64 = "--m1 1 --m2 64 --L1 0.5 --a1 0.25 --I1 0.0625 --L2 2 --g 16.0".split()
M1024 = "--m1 1 --m2 1024 --L1 0.5 --a1 0.25 --I1 0.0625 --L2 2 --g 1.0".split()
CASES = [("light long first link, L2 = 1", L1, "1", E) for E in ("2010.5", "2016", "2018", "2025", "2030", "2035")]
CASES += [("light long first link, L2 = 0.2", L02, "1", E) for E in ("2020", "2030")]
CASES += [("heavy second arm m2 = 31.6", HEAVY, "2", E) for E in ("728", "730", "771")]
CASES += [("pendulum E's geometry, m2 = 64", M64, "2", E) for E in ("4405.6",)]
CASES += [("pendulum E's geometry, m2 = 1024", M1024, "2", E) for E in ("4403.35",)]
def ev(ff, q, P, arm, E):
    r = subprocess.run(["timeout", "120", ff, "eval", q, "--arm", arm, "--energy", E] + P,
                       capture_output=True, text=True)
    if r.returncode:
        return None, r.stderr.strip().splitlines()[-1][:160] if r.stderr.strip() else f"exit {r.returncode}"
    j = json.loads(r.stdout)
    return j["value"], j["error_estimate"]
for name, P, arm, E in CASES:
    row = {}
    binaries = [(f"before{i + 1}", b) for i, b in enumerate(BEFORE)] + [("after", A)]
    for label, ff in binaries:
        row[label] = {q: ev(ff, q, P, arm, E) for q in ("period", "action", "multiplier")}
    ta = row["after"]["period"][0]
    multiples = []
    for label, _ in binaries[:-1]:
        tb = row[label]["period"][0]
        multiples.append(f"{label} {float(tb) / float(ta):.12f}" if tb and ta else f"{label} -")
    print(f"{name} | arm {arm} | E {E} | multiple " + ", ".join(multiples))
    for label, _ in binaries:
        for q in ("period", "action", "multiplier"):
            v, e = row[label][q]
            print(f"   {label} {q}: " + (f"{v} (estimate {e})" if v else f"error: {e}"))
