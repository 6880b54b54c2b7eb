"""The independent mpmath route at high precision (label "verify": `bash setup.sh verify`):
Omega above E_max against 16 pi^2 E(-1) at mp:1000, and Omega, f1 and f2 of the egalitarian
pendulum against mpmath_reference.py's formulas (adaptive mpmath quadrature of the same integrals,
written independently of the C++ code) at mp:300. Fails when a relative difference exceeds
10^-(N-10) at mp:N.

usage: python3 mpmath_high_precision.py path/to/flipflux
"""
import json
import os
import subprocess
import sys
import time

import mpmath as mp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mpmath_reference as ref  # noqa: E402  (the formulas; its precision is set below)


def flipflux(exe, args):
    start = time.time()
    out = subprocess.run(f"{exe} eval {args}", shell=True, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(f"flipflux eval {args}: {out.stderr.strip()}")
    return mp.mpf(json.loads(out.stdout)["value"]), time.time() - start


def check(label, got, want, digits, seconds):
    rel = abs(got - want) / abs(want)
    correct = -mp.log10(rel) if rel > 0 else mp.inf
    print(f"{label}: {mp.nstr(correct, 5)} digits at mp:{digits} ({seconds:.3g} s)")
    return rel <= mp.mpf(10) ** (-(digits - 10))


def main():
    exe = sys.argv[1]
    ok = True
    mp.mp.dps = 1020
    got, s = flipflux(exe, "omega --energy 10 --precision mp:1000")
    ok &= check("omega E = 10 against 16 pi^2 E(-1)", got, 16 * mp.pi**2 * mp.ellipe(-1), 1000, s)
    mp.mp.dps = 320
    k = ref.coeffs()
    for arm, energy in ((2, "3"), (1, "5")):
        E = mp.mpf(energy)
        got, s = flipflux(exe, f"flux-upright --energy {energy} --arm {arm} --precision mp:300")
        ok &= check(f"flux-upright arm {arm} E = {energy}", got, ref.curve_flux(E, k, arm, 0),
                    300, s)
        amp = ref.centre_ratio(k, 1, -1) if arm == 2 else 1 / ref.centre_ratio(k, -1, 1)
        got, s = flipflux(exe, f"flux-approx --energy {energy} --arm {arm} --precision mp:300")
        ok &= check(f"flux-approx arm {arm} E = {energy}", got, ref.curve_flux(E, k, arm, amp),
                    300, s)
    got, s = flipflux(exe, "omega --energy 3 --precision mp:300")
    ok &= check("omega E = 3", got, ref.omega(mp.mpf(3), k), 300, s)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
