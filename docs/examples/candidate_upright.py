#!/usr/bin/env python3
"""A candidate implementation in another language, for `flipflux validate` (docs/validating.md).

The paper's pendulum (m1 = m2 = L1 = L2 = g = 1) above the potential maximum E_max = 6, where
every configuration is allowed and the quantities have closed forms (derived in docs/theory.md):

    Omega(E)        = 16 pi^2 E(-1)                      (independent of E for E >= 6)
    f1(E), arm 2    = 4 sqrt(A) * integral of sqrt(2 K(theta1)) over theta1 in [-pi, pi],
                      K = E - V(theta1, pi) = (E - 2) (1 - m sin^2(theta1 / 2)), m = 4 / (E - 2)
                    = 32 sqrt(E - 2) E(m)
    R1 = f1 / Omega

E(m) is the complete elliptic integral of the second kind in the parameter convention
(mpmath.ellipe). Writes quantity,arm,energy,value rows to stdout with 30 significant digits.
Usage: candidate_upright.py [--corrupt]   (--corrupt changes one value in its 9th digit)
"""
import sys

import mpmath as mp

mp.mp.dps = 40
ENERGIES = ["6.5", "7", "7.5", "8", "9", "10", "12", "15", "20", "25", "30", "40", "50", "60",
            "70", "80", "90", "100"]


def omega():
    return 16 * mp.pi**2 * mp.ellipe(-1)


def flux_upright_arm2(energy):
    e = mp.mpf(energy)
    return 32 * mp.sqrt(e - 2) * mp.ellipe(4 / (e - 2))


def main():
    corrupt = "--corrupt" in sys.argv[1:]
    print("quantity,arm,energy,value")
    for i, e in enumerate(ENERGIES):
        f1 = flux_upright_arm2(e)
        rate = f1 / omega()
        if corrupt and i == 3:
            rate *= 1 + mp.mpf("3e-9")  # one value off in its 9th significant digit
        print(f"omega,,{e},{mp.nstr(omega(), 30)}")
        print(f"flux-upright,2,{e},{mp.nstr(f1, 30)}")
        print(f"rate-upright,2,{e},{mp.nstr(rate, 30)}")


if __name__ == "__main__":
    main()
