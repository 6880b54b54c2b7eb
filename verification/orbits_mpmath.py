"""An independent route for saddle orbits, outside C++: Hamilton's equations written again in
absolute angles (not the saddle frame), integrated by mpmath's Taylor-series ODE solver at 36
digits from the start state and period that `flipflux orbit --precision quad` prints. Checks, for
two orbits (egalitarian arm 2 at E = 3; an unequal pendulum's arm 1):
  - the start is at the saddle with H = E            (|H - E| / (E - E_s) <= 1e-30)
  - at t = T/4 both momenta vanish (a brake point)   (|l(T/4)| / |l0| <= 1e-28, which also pins T:
                                                      dl/dt = -grad V there is O(1))
  - the action 4 int_0^{T/4} l.w dt equals `flipflux eval action --precision quad` (<= 1e-29)
Fails (exit 1) otherwise. About a minute per orbit.

usage: python3 orbits_mpmath.py path/to/flipflux
"""
import subprocess
import sys

import mpmath as mp

mp.mp.dps = 36


def coefficients(m1=1, m2=1, L1=1, L2=1, g=1):
    m1, m2, L1, L2, g = [mp.mpf(str(x)) for x in (m1, m2, L1, L2, g)]
    # point masses: A = (m1+m2) L1^2, B = m2 L2^2, C = m2 L1 L2, alpha = (m1+m2) g L1, beta = m2 g L2
    return (m1 + m2) * L1**2, m2 * L2**2, m2 * L1 * L2, (m1 + m2) * g * L1, m2 * g * L2


def check(exe, energy, arm, params):
    A, B, C, al, be = coefficients(**params)
    opts = []
    for k, v in params.items():
        opts += [f"--{k}", str(v)]
    base = ["--energy", energy, "--arm", str(arm), "--precision", "quad"] + opts
    csv = subprocess.run([exe, "orbit", "--samples", "2"] + base, capture_output=True, text=True,
                         check=True).stdout.strip().split("\n")
    start = [mp.mpf(v) for v in csv[1].split(",")]
    T = mp.mpf(csv[2].split(",")[0])
    action = subprocess.run([exe, "eval", "action"] + base, capture_output=True, text=True,
                            check=True).stdout
    F_cli = mp.mpf(action.split('"value": "')[1].split('"')[0])
    E = mp.mpf(energy)
    Es = 2 * be if arm == 2 else 2 * al

    def H(t1, t2, l1, l2):
        c = mp.cos(t1 - t2)
        det = A * B - C * C * c * c
        return (B * l1 * l1 - 2 * C * c * l1 * l2 + A * l2 * l2) / (2 * det) + \
            al * (1 - mp.cos(t1)) + be * (1 - mp.cos(t2))

    def rhs(t, y):
        t1, t2, l1, l2, _ = y
        c, s = mp.cos(t1 - t2), mp.sin(t1 - t2)
        det = A * B - C * C * c * c
        w1 = (B * l1 - C * c * l2) / det
        w2 = (-C * c * l1 + A * l2) / det
        P = C * s * w1 * w2
        return [w1, w2, -P - al * mp.sin(t1), P - be * mp.sin(t2), l1 * w1 + l2 * w2]

    t1, t2, l1, l2 = start[1:]
    ok = True
    dH = abs(H(t1, t2, l1, l2) - E) / (E - Es)
    y = mp.odefun(rhs, 0, [t1, t2, l1, l2, mp.mpf(0)])(T / 4)
    brake = max(abs(y[2]), abs(y[3])) / max(abs(l1), abs(l2))
    dF = abs(4 * y[4] - F_cli) / F_cli
    print(f"  arm {arm} E = {energy} {params}: T = {mp.nstr(T, 30)}; |H - E|/(E - E_s) = "
          f"{mp.nstr(dH, 3)}, |l(T/4)|/|l0| = {mp.nstr(brake, 3)}, action rel. diff "
          f"{mp.nstr(dF, 3)}")
    ok = dH <= mp.mpf("1e-30") and brake <= mp.mpf("1e-28") and dF <= mp.mpf("1e-29")
    return ok


def main():
    exe = sys.argv[1]
    results = [check(exe, "3", 2, {}), check(exe, "6.6", 1, {"m1": 2, "L2": "0.6"})]
    if not all(results):
        print("orbits_mpmath: FAILED")
        sys.exit(1)
    print("orbits_mpmath: all checks passed")


if __name__ == "__main__":
    main()
