"""An independent route for reference trajectories, outside C++: Hamilton's equations written
again and integrated by mpmath's Taylor-series ODE solver at 50 digits from the initial state, at
the event times that `flipflux trajectory --precision mp:40` prints (the upright criterion of both
arms, an unequal pendulum with rigid-link inertia included). Checks, for every event:
  - the flip angle is pi (mod 2 pi) there            (|theta - pi - 2 pi k| <= 1e-32: the event
                                                      time is right to ~1e-32 / |theta'|)
  - it moves in the event's direction                (sign of theta')
and that the final state at T = 6 agrees with `--out`'s last row to 1e-32. Fails (exit 1)
otherwise. A few minutes.

usage: python3 trajectory_mpmath.py path/to/flipflux
"""
import os
import subprocess
import sys
import tempfile

import mpmath as mp

mp.mp.dps = 50


def check(exe, state, params):
    m1, m2, L1, L2 = [mp.mpf(str(params.get(k, 1))) for k in ("m1", "m2", "L1", "L2")]
    a1, a2 = [mp.mpf(str(params.get(k, params.get("L" + k[1], 1)))) for k in ("a1", "a2")]
    I1, I2 = [mp.mpf(str(params.get(k, 0))) for k in ("I1", "I2")]
    g = mp.mpf(str(params.get("g", 1)))
    # rigid links: centres of mass at a1, a2 from the pivots, moments of inertia I1, I2 about them
    A = m1 * a1**2 + I1 + m2 * L1**2
    B = m2 * a2**2 + I2
    C = m2 * L1 * a2
    al = (m1 * a1 + m2 * L1) * g
    be = m2 * a2 * g
    opts = []
    for k, v in params.items():
        opts += [f"--{k}", str(v)]
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "states.csv")
        events = subprocess.run([exe, "trajectory", "--state", state, "--time", "6",
                                 "--criteria", "upright", "--precision", "mp:40", "--out", out] +
                                opts, capture_output=True, text=True, check=True).stdout
        final = [mp.mpf(v) for v in open(out).read().strip().split("\n")[-1].split(",")[1:5]]
    rows = [r.split(",") for r in events.strip().split("\n")[1:]]

    def rhs(t, y):
        t1, t2, l1, l2 = y
        c, s = mp.cos(t1 - t2), mp.sin(t1 - t2)
        det = A * B - C * C * c * c
        w1 = (B * l1 - C * c * l2) / det
        w2 = (-C * c * l1 + A * l2) / det
        P = C * s * w1 * w2
        return [w1, w2, -P - al * mp.sin(t1), P - be * mp.sin(t2)]

    y0 = [mp.mpf(v) for v in state.split(",")]
    f = mp.odefun(rhs, 0, y0)
    worst, ok = mp.mpf(0), len(rows) >= 2
    for t, arm, _, direction in rows:
        y = f(mp.mpf(t))
        k = 1 if arm == "2" else 0
        th = y[k]
        off = th - mp.pi - 2 * mp.pi * mp.nint((th - mp.pi) / (2 * mp.pi))
        worst = max(worst, abs(off))
        speed = rhs(0, y)[k]
        ok = ok and (speed > 0) == (direction == "1")
    y = f(mp.mpf(6))
    dstate = max(abs(y[i] - final[i]) for i in range(4))
    print(f"  state {state} {params}: {len(rows)} events; max |theta - pi (mod 2 pi)| = "
          f"{mp.nstr(worst, 3)}; final state max diff {mp.nstr(dstate, 3)}")
    return ok and worst <= mp.mpf("1e-32") and dstate <= mp.mpf("1e-32")


def main():
    exe = sys.argv[1]
    results = [check(exe, "2.5,3.0,1.2,1.0", {}),
               check(exe, "1.2,2.9,0.4,0.6", {"m1": 2, "L2": "0.7", "a1": "0.5", "I1": "0.1"})]
    if not all(results):
        print("trajectory_mpmath: FAILED")
        sys.exit(1)
    print("trajectory_mpmath: all checks passed")


if __name__ == "__main__":
    main()
